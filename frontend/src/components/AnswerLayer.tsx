/**
 * The answer, drawn by the phone over its own photo from the state's JSON, in the design of
 * the server's overlay (answerLayer.ts): an open frame of corner brackets around where the
 * friend is, the region's outline only when it is larger than a person, "friend" on a short
 * leader beside it; the curve they are on when there is no point yet; an arrow at the photo's
 * border when they are outside it. Strokes and labels keep their size on the screen at every
 * zoom, so they never grow over the friend; the frame is drawn last, on top.
 *
 * It also publishes what it drew (data attributes, photo px), which the browser tests read.
 */

import type { AnswerView } from "../answer";
import { answerFrame, bracketPath, conicPoints, edgeArrow, screenFrame, type Frame } from "../answerLayer";
import { FRIEND_COLOUR, OUTLINE_COLOUR } from "../palette";
import type { Ellipse } from "../types";
import { toScreen, type Point, type Size, type ViewTransform } from "../viewTransform";

/** Screen px: the friend's strokes and their dark outline (it reads on bright photos). */
const STROKE = 2.5;
const OUTLINE = 5;
/** The leader from the frame to its label, and the label's font size, screen px. */
const LEADER = 12;
const FONT = 15;
/** The curve is dotted, a dot about every this many screen px: it runs through the friend,
 * who shows between the dots. */
const CURVE_STEP_CSS = 7;
const CURVE_DOT = 3;
const CURVE_OUTLINE = 4.5;
/** The arrow at the photo's border: its length, and its distance inside the border. */
const BORDER_ARROW = 44;
const BORDER_INSET = 30;

/** The frame to draw for an answer, or null when there is no point. */
export function frameOf(answer: AnswerView, photo: Size): Frame | null {
  const position = answer.position;
  return position ? answerFrame(position, position.ellipse, photo) : null;
}

/**
 * The frame's label: "friend" around a 95 % region, "friend?" around a likely spot. Null: no
 * frame, on this phone's own mark, refined (its thin ring, "Friend", is the answer: a frame
 * around it would only hide more of the person).
 */
export function frameLabel(answer: AnswerView, frame: Frame): string | null {
  if (answer.position?.how === "marked") return null;
  return frame.sure ? "friend" : "friend?";
}

interface Props {
  answer: AnswerView;
  transform: ViewTransform;
  view: Size;
  photo: Size;
  /** Screen px at the view's top covered by the status: no label goes there. */
  clearTop: number;
}

export function AnswerLayer({ answer, transform: t, view, photo, clearTop }: Props) {
  const frame = frameOf(answer, photo);
  const label = frame ? frameLabel(answer, frame) : null;
  const inPhoto = frame
    ? frame.centre.x >= 0 && frame.centre.y >= 0 && frame.centre.x <= photo.width && frame.centre.y <= photo.height
    : false;
  return (
    <svg class="answer-layer" width={view.width} height={view.height} aria-hidden="true" data-testid="answer-layer">
      {answer.curve && <Curve conic={answer.curve} transform={t} photo={photo} />}
      {frame && inPhoto && label !== null && (
        <FrameMark frame={frame} label={label} clearTop={clearTop} transform={t} />
      )}
      {frame && !inPhoto && <BorderArrow target={frame.centre} transform={t} photo={photo} />}
    </svg>
  );
}

interface FrameProps {
  frame: Frame;
  label: string;
  clearTop: number;
  transform: ViewTransform;
}

/** Brackets around the region (its outline inside when larger than a person), labelled. */
function FrameMark({ frame, label, clearTop, transform }: FrameProps) {
  const { centre, half } = screenFrame(frame, transform);
  const box = {
    "data-x0": String(frame.centre.x - frame.half.x),
    "data-y0": String(frame.centre.y - frame.half.y),
    "data-x1": String(frame.centre.x + frame.half.x),
    "data-y1": String(frame.centre.y + frame.half.y),
  };
  const path = bracketPath(centre, half);
  // The label above the frame, else below when there is no room above (the top of the view,
  // or under the status).
  const above = centre.y - half.y - LEADER - FONT >= clearTop;
  const edge = above ? centre.y - half.y : centre.y + half.y;
  const end = above ? edge - LEADER : edge + LEADER;
  return (
    <g data-testid="answer-frame" data-sure={String(frame.sure)} data-outlined={String(frame.outlined)} {...box}>
      {frame.outlined && frame.region && <Outline region={frame.region} transform={transform} />}
      <line x1={centre.x} y1={edge} x2={centre.x} y2={end} stroke={OUTLINE_COLOUR} stroke-width={OUTLINE} stroke-linecap="round" />
      <line x1={centre.x} y1={edge} x2={centre.x} y2={end} stroke={FRIEND_COLOUR} stroke-width={STROKE} stroke-linecap="round" />
      <path d={path} fill="none" stroke={OUTLINE_COLOUR} stroke-width={OUTLINE} stroke-linecap="round" stroke-linejoin="round" />
      <path d={path} fill="none" stroke={FRIEND_COLOUR} stroke-width={STROKE} stroke-linecap="round" stroke-linejoin="round" />
      <text
        class="answer-label"
        x={centre.x}
        y={above ? end - 4 : end + FONT}
        text-anchor="middle"
        font-size={FONT}
        fill={FRIEND_COLOUR}
        stroke={OUTLINE_COLOUR}
        stroke-width="4"
        paint-order="stroke"
      >
        {label}
      </text>
    </g>
  );
}

/** The 95 % region's outline, thin. */
function Outline({ region, transform: t }: { region: Ellipse; transform: ViewTransform }) {
  const c = toScreen(t, { x: region.center[0], y: region.center[1] });
  const attributes = {
    cx: c.x,
    cy: c.y,
    rx: region.axes[0] * t.scale,
    ry: region.axes[1] * t.scale,
    transform: `rotate(${region.angle_deg} ${c.x} ${c.y})`,
    fill: "none",
  };
  return (
    <g data-testid="answer-region">
      <ellipse {...attributes} stroke={OUTLINE_COLOUR} stroke-width={3.5} />
      <ellipse {...attributes} stroke={FRIEND_COLOUR} stroke-width={1.5} />
    </g>
  );
}

/** The curve the friend is on, dotted: dots where it crosses the photo's rows and columns. */
function Curve({ conic, transform: t, photo }: { conic: number[][]; transform: ViewTransform; photo: Size }) {
  const points = conicPoints(conic, photo, CURVE_STEP_CSS / t.scale);
  const path = points
    .map((p) => toScreen(t, p))
    .map((p) => `M${p.x.toFixed(1)} ${p.y.toFixed(1)}h0`)
    .join("");
  return (
    <g data-testid="answer-curve" data-points={String(points.length)}>
      <path d={path} stroke={OUTLINE_COLOUR} stroke-width={CURVE_OUTLINE} stroke-linecap="round" />
      <path d={path} stroke={FRIEND_COLOUR} stroke-width={CURVE_DOT} stroke-linecap="round" />
    </g>
  );
}

/** An arrow inside the photo's border, pointing from the photo's centre towards the friend. */
function BorderArrow({ target, transform: t, photo }: { target: Point; transform: ViewTransform; photo: Size }) {
  const corner = toScreen(t, { x: 0, y: 0 });
  const far = toScreen(t, { x: photo.width, y: photo.height });
  const box = { left: corner.x, top: corner.y, right: far.x, bottom: far.y };
  const arrow = edgeArrow(toScreen(t, target), box, BORDER_INSET);
  if (!arrow) return null;
  const { at, angle } = arrow;
  const back = { x: at.x - BORDER_ARROW * Math.cos(angle), y: at.y - BORDER_ARROW * Math.sin(angle) };
  const head = (side: number): Point => ({
    x: at.x - 14 * Math.cos(angle + side * 0.5),
    y: at.y - 14 * Math.sin(angle + side * 0.5),
  });
  const path = `M${back.x} ${back.y}L${at.x} ${at.y}M${head(1).x} ${head(1).y}L${at.x} ${at.y}L${head(-1).x} ${head(-1).y}`;
  return (
    <g data-testid="answer-border-arrow">
      <path d={path} fill="none" stroke={OUTLINE_COLOUR} stroke-width={OUTLINE + 1} stroke-linecap="round" />
      <path d={path} fill="none" stroke={FRIEND_COLOUR} stroke-width={STROKE + 1} stroke-linecap="round" />
      <text
        x={back.x - 18 * Math.cos(angle)}
        y={back.y - 18 * Math.sin(angle) + FONT / 3}
        text-anchor="middle"
        font-size={FONT}
        fill={FRIEND_COLOUR}
        stroke={OUTLINE_COLOUR}
        stroke-width="4"
        paint-order="stroke"
      >
        friend
      </text>
    </g>
  );
}
