/**
 * The SVG of the answer's marks, in screen px, shared by the two places a phone draws the
 * server's drawing: over its photo (AnswerLayer.tsx, placed by the view's zoom) and over its
 * live camera view (live/LiveView.tsx, placed by the phone's turn). Each caller maps the
 * shapes' photo px to the screen; what is drawn there, and how thick, is said once here.
 */

import { BAND_OPACITY, FRIEND_COLOUR, OUTLINE_COLOUR } from "../palette";
import type { Point } from "../viewTransform";

/** Screen px: the friend's strokes and their dark outline (it reads on bright photos). */
export const STROKE = 2.5;
export const OUTLINE = 5;
/** The leader from the frame to its label, and the label's font size, screen px. */
export const LEADER = 12;
export const FONT = 15;
/** The least half-size of the frame on screen, CSS px: a frame is never a dot. */
export const MIN_FRAME_CSS = 12;
/** The curve is dotted, a dot every this many screen px: it runs through the friend, who
 * shows between the dots. */
export const CURVE_STEP_CSS = 7;
const CURVE_DOT = 3;
const CURVE_OUTLINE = 4.5;
/** The stretch of the level the compasses point to: the curve's dots twice as big and as far
 * apart (bolder, and the friend still shows between them). */
const STRETCH_SCALE = 2;

/** Polylines as one SVG path, each point placed on the screen by `map` (null: not drawn). */
export function pathOf<P>(lines: ReadonlyArray<ReadonlyArray<P>>, map: (p: P) => Point | null): string {
  return lines
    .map((line) =>
      line
        .map(map)
        .filter((s): s is Point => s !== null)
        .map((s, i) => `${i === 0 ? "M" : "L"}${s.x.toFixed(1)} ${s.y.toFixed(1)}`)
        .join(""),
    )
    .join("");
}

interface LabelProps {
  /** Where the label's baseline is centred, screen px. */
  x: number;
  y: number;
  label: string;
  class?: string;
}

/** A mark's words, in the friend's colour outlined in dark (they read on bright photos). */
function OutlinedLabel({ x, y, label, class: className }: LabelProps) {
  return (
    <text
      class={className}
      x={x}
      y={y}
      text-anchor="middle"
      font-size={FONT}
      fill={FRIEND_COLOUR}
      stroke={OUTLINE_COLOUR}
      stroke-width="4"
      paint-order="stroke"
    >
      {label}
    </text>
  );
}

interface LabelledProps {
  /** The frame's brackets, an SVG path in screen px. */
  brackets: string;
  centre: Point;
  /** The frame's top and bottom on the screen, px. */
  top: number;
  bottom: number;
  /** Whether the label goes above the frame (else below). */
  above: boolean;
  label: string;
}

/** The frame's brackets and "friend" on its leader, outlined. */
export function LabelledFrame({ brackets, centre, top, bottom, above, label }: LabelledProps) {
  const edge = above ? top : bottom;
  const end = above ? edge - LEADER : edge + LEADER;
  return (
    <>
      <line x1={centre.x} y1={edge} x2={centre.x} y2={end} stroke={OUTLINE_COLOUR} stroke-width={OUTLINE} stroke-linecap="round" />
      <line x1={centre.x} y1={edge} x2={centre.x} y2={end} stroke={FRIEND_COLOUR} stroke-width={STROKE} stroke-linecap="round" />
      <path d={brackets} fill="none" stroke={OUTLINE_COLOUR} stroke-width={OUTLINE} stroke-linecap="round" stroke-linejoin="round" />
      <path d={brackets} fill="none" stroke={FRIEND_COLOUR} stroke-width={STROKE} stroke-linecap="round" stroke-linejoin="round" />
      <OutlinedLabel class="answer-label" x={centre.x} y={above ? end - 4 : end + FONT} label={label} />
    </>
  );
}

interface DottedProps {
  /** The curve, an SVG path in screen px. */
  path: string;
  /** The band's width on the screen, px (0: none). */
  band: number;
  /** The stretch the compasses point to, an SVG path, or null. */
  stretch: string | null;
  /** Published with the stretch (photo px) for the browser tests. */
  stretchPoints?: string;
}

/** The curve the friend is on, dotted, in its band when it has one, and over the band,
 * bolder, the stretch the phones' compasses point to when they told it (a hint). */
export function DottedCurve({ path, band, stretch, stretchPoints }: DottedProps) {
  const dots = { fill: "none", "stroke-linecap": "round", "stroke-dasharray": `0 ${CURVE_STEP_CSS}` } as const;
  const bold = { ...dots, "stroke-dasharray": `0 ${STRETCH_SCALE * CURVE_STEP_CSS}` } as const;
  return (
    <>
      {band > 0 && (
        <path
          data-testid="answer-band"
          d={path}
          fill="none"
          stroke={FRIEND_COLOUR}
          stroke-opacity={BAND_OPACITY}
          stroke-width={band}
          stroke-linecap="butt"
          stroke-linejoin="round"
        />
      )}
      <path d={path} {...dots} stroke={OUTLINE_COLOUR} stroke-width={CURVE_OUTLINE} />
      <path d={path} {...dots} stroke={FRIEND_COLOUR} stroke-width={CURVE_DOT} />
      {stretch !== null && (
        <g data-testid="answer-stretch" data-points={stretchPoints}>
          <path d={stretch} {...bold} stroke={OUTLINE_COLOUR} stroke-width={STRETCH_SCALE * CURVE_OUTLINE} />
          <path d={stretch} {...bold} stroke={FRIEND_COLOUR} stroke-width={STRETCH_SCALE * CURVE_DOT} />
        </g>
      )}
    </>
  );
}

/** An arrow's length and its head's, screen px. */
const ARROW = 44;
const ARROW_HEAD = 14;

interface ArrowProps {
  tip: Point;
  /** Its direction, radians from the screen's x axis (y down). */
  angle: number;
  label: string;
  /** How far behind the arrow's tail its label sits, screen px. */
  labelBack: number;
}

/** An outlined arrow pointing at `tip`, its label behind its tail. */
export function ArrowMark({ tip, angle, label, labelBack }: ArrowProps) {
  const back = { x: tip.x - ARROW * Math.cos(angle), y: tip.y - ARROW * Math.sin(angle) };
  const head = (side: number): Point => ({
    x: tip.x - ARROW_HEAD * Math.cos(angle + side * 0.5),
    y: tip.y - ARROW_HEAD * Math.sin(angle + side * 0.5),
  });
  const path = `M${back.x} ${back.y}L${tip.x} ${tip.y}M${head(1).x} ${head(1).y}L${tip.x} ${tip.y}L${head(-1).x} ${head(-1).y}`;
  return (
    <>
      <path d={path} fill="none" stroke={OUTLINE_COLOUR} stroke-width={OUTLINE + 1} stroke-linecap="round" />
      <path d={path} fill="none" stroke={FRIEND_COLOUR} stroke-width={STROKE + 1} stroke-linecap="round" />
      <OutlinedLabel
        x={back.x - labelBack * Math.cos(angle)}
        y={back.y - labelBack * Math.sin(angle) + FONT / 3}
        label={label}
      />
    </>
  );
}
