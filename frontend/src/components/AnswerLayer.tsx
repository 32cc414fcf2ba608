/**
 * The answer, drawn by the phone over its own photo: a thin SVG renderer of the shapes the
 * server computed for this photo (`answer.in_photo[you].drawing`, shared_solver/drawing:
 * the same shapes its OpenCV overlay draws). Corner brackets around where the friend is, the
 * region's outline inside when it is larger than a person, "friend" on a short leader beside;
 * the curve they are on when there is no point yet; an arrow at the photo's border when they
 * are outside it. Only stroke widths, font sizes and screen lengths are chosen here: they keep
 * their size on the screen at every zoom, so they never grow over the friend; the frame is
 * drawn last, on top.
 *
 * It also publishes what it drew (data attributes, photo px), which the browser tests read:
 * the curve's points too, as the server simplified them (within 0.25 px of the curve).
 */

import { t as tr } from "../i18n";
import { drawnLabel } from "../i18n/server";
import type { AnswerView } from "../answer";
import { FRIEND_COLOUR, OUTLINE_COLOUR } from "../palette";
import type { ArrowShape, CurveShape, FrameShape } from "../types";
import { toScreen, type Point, type Size, type ViewTransform } from "../viewTransform";
import { ArrowMark, DottedCurve, FONT, LEADER, LabelledFrame, MIN_FRAME_CSS, pathOf as screenPath } from "./answerMarks";

/** The region's outline, thinner than the friend's strokes. */
const REGION_STROKE = 1.5;
const REGION_OUTLINE = 3.5;

/** The box the view brings into sight for this answer, photo px (the frame's, also when the
 * friend is outside the photo), or null when there is no point. */
export function answerBox(answer: AnswerView): { centre: Point; half: Point } | null {
  const focus = answer.position ? answer.drawing?.focus : null;
  return focus ? { centre: point(focus.centre), half: point(focus.half) } : null;
}

function point([x, y]: readonly number[]): Point {
  return { x: x ?? Number.NaN, y: y ?? Number.NaN };
}

interface Props {
  answer: AnswerView;
  transform: ViewTransform;
  view: Size;
  /** Screen px at the view's top covered by the status: no label goes there. */
  clearTop: number;
}

export function AnswerLayer({ answer, transform: t, view, clearTop }: Props) {
  const drawing = answer.drawing;
  // On this phone's own mark, refined, no frame: its thin ring ("Friend") is the answer, and
  // a frame around it would only hide more of the person.
  const frame = answer.position?.how === "marked" ? null : (drawing?.frame ?? null);
  return (
    <svg class="answer-layer" width={view.width} height={view.height} aria-hidden="true" data-testid="answer-layer">
      {drawing?.curve && <Curve curve={drawing.curve} transform={t} />}
      {frame && <FrameMark frame={frame} clearTop={clearTop} transform={t} />}
      {drawing?.arrow && <BorderArrow arrow={drawing.arrow} transform={t} />}
    </svg>
  );
}

/** Polylines in photo px as one SVG path, each point placed on the screen by `map`. */
function pathOf(lines: ReadonlyArray<ReadonlyArray<readonly number[]>>, map: (p: Point) => Point): string {
  return screenPath(lines, (p) => map(point(p)));
}

interface FrameProps {
  frame: FrameShape;
  clearTop: number;
  transform: ViewTransform;
}

/** Brackets around the region (its outline inside when larger than a person), labelled. */
function FrameMark({ frame, clearTop, transform: t }: FrameProps) {
  const centre = toScreen(t, point(frame.centre));
  const [hx, hy] = frame.half;
  // A frame far smaller than a finger on screen is spread to the least size about its centre.
  const spread = (h: number): number => Math.max(1, MIN_FRAME_CSS / (t.scale * h));
  const sx = spread(hx);
  const sy = spread(hy);
  const bracket = (p: Point): Point => {
    const s = toScreen(t, p);
    return { x: centre.x + sx * (s.x - centre.x), y: centre.y + sy * (s.y - centre.y) };
  };
  const box = {
    "data-x0": String(frame.centre[0] - hx),
    "data-y0": String(frame.centre[1] - hy),
    "data-x1": String(frame.centre[0] + hx),
    "data-y1": String(frame.centre[1] + hy),
  };
  const path = pathOf(frame.brackets, bracket);
  const half = { x: sx * t.scale * hx, y: sy * t.scale * hy };
  // The label where the drawing puts it (above the frame when there is room on the photo),
  // below when above is off the view or under the status.
  const above = frame.label_above && centre.y - half.y - LEADER - FONT >= clearTop;
  const outline = frame.outline ?? [];
  const outlined = outline.length > 0;
  return (
    <g data-testid="answer-frame" data-sure={String(frame.sure)} data-outlined={String(outlined)} {...box}>
      {outlined && <Outline lines={outline} transform={t} />}
      <LabelledFrame brackets={path} centre={centre} top={centre.y - half.y} bottom={centre.y + half.y} above={above} label={drawnLabel(frame.label)} />
    </g>
  );
}

/** The 95 % region's outline, thin. */
function Outline({ lines, transform: t }: { lines: ReadonlyArray<ReadonlyArray<readonly number[]>>; transform: ViewTransform }) {
  const path = pathOf(lines, (p) => toScreen(t, p));
  return (
    <g data-testid="answer-region">
      <path d={path} fill="none" stroke={OUTLINE_COLOUR} stroke-width={REGION_OUTLINE} stroke-linejoin="round" />
      <path d={path} fill="none" stroke={FRIEND_COLOUR} stroke-width={REGION_STROKE} stroke-linejoin="round" />
    </g>
  );
}

/** The curve the friend is on, dotted: a round dot every {@link CURVE_STEP_CSS} screen px;
 * in its band when it has one (the level from gravity: the band is in photo px, so it grows
 * with the zoom, as the overlay's does), and over the band, bolder, the stretch the phones'
 * compasses point to when they told it (a hint). */
function Curve({ curve, transform: t }: { curve: CurveShape; transform: ViewTransform }) {
  const path = pathOf(curve.polylines, (p) => toScreen(t, p));
  const band = curve.halfwidth ?? null;
  const stretch = curve.stretch?.length ? pathOf(curve.stretch, (p) => toScreen(t, p)) : null;
  return (
    <g
      data-testid="answer-curve"
      data-pieces={String(curve.polylines.length)}
      data-points={JSON.stringify(curve.polylines)}
      data-halfwidth={band === null ? undefined : String(band)}
    >
      <DottedCurve path={path} band={band === null ? 0 : 2 * band * t.scale} stretch={stretch} stretchPoints={JSON.stringify(curve.stretch)} />
    </g>
  );
}

/** The arrow inside the photo's border, pointing from the photo's centre towards the friend. */
function BorderArrow({ arrow, transform: t }: { arrow: ArrowShape; transform: ViewTransform }) {
  const at = toScreen(t, point(arrow.tip));
  const angle = Math.atan2(arrow.direction[1], arrow.direction[0]);
  return (
    <g data-testid="answer-border-arrow" data-tip-x={String(arrow.tip[0])} data-tip-y={String(arrow.tip[1])}>
      <ArrowMark tip={at} angle={angle} label={tr("answer.drawnFriend")} labelBack={18} />
    </g>
  );
}
