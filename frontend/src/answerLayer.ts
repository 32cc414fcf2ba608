/**
 * The answer's drawing, as geometry: the open frame around where the friend is, the curve
 * they are on, and where the arrow goes when they are out of sight. The phone draws it from
 * the state's JSON (components/AnswerLayer.tsx) in the design of the server's overlay
 * (shared_solver/drawing/overlay.py): corner brackets around the 95 % region, never smaller
 * than a person far across a hall, the region's outline only when it is larger than a person,
 * and "friend" on a short leader beside; nothing is drawn on the friend.
 *
 * Sizes of the frame are in photo px (it frames a person, who grows as the view zooms);
 * strokes and labels are in screen px (they keep their size, so they never grow over the
 * friend).
 */

import type { Ellipse } from "./types";
import type { Point, Size, ViewTransform } from "./viewTransform";

/** A person far across a hall, as a fraction of the photo's diagonal (overlay.py's
 * `frame_half`): the least half-size of the frame. */
export const PERSON_FRACTION = 1 / 55;
/** The region's outline is drawn when its short semi-axis is at least this many least
 * half-sizes: narrower, it would run over the friend the brackets frame anyway. (The
 * server's overlay.py asks this of the long semi-axis: a thin region's outline then crosses
 * a person standing in it, which the phone, showing the person, avoids.) */
export const OUTLINED_REGION = 0.6;
/** A bracket's arm, as a fraction of the frame's shorter half-side (overlay.py). */
export const BRACKET_ARM = 0.4;
/** The least half-size of the frame on screen, CSS px: a frame is never a dot. */
export const MIN_FRAME_CSS = 12;

/** The frame around the friend, in photo px. */
export interface Frame {
  centre: Point;
  /** Half its width and height. */
  half: { x: number; y: number };
  /** Whether the region's outline is drawn inside (a region larger than a person). */
  outlined: boolean;
  /** Whether a 95 % region is claimed ("friend"), or only a likely spot ("friend?"). */
  sure: boolean;
  /** The 95 % region (its outline is drawn when `outlined`). */
  region: Ellipse | null;
}

/** How tall a person far across the hall is in this photo, px (the frame's least half-size). */
export function personSize(photo: Size): number {
  return Math.hypot(photo.width, photo.height) * PERSON_FRACTION;
}

/** The axis-aligned half-sizes of an ellipse (semi-axes `axes`, first axis `angle_deg` from x). */
export function ellipseReach(ellipse: Ellipse): { x: number; y: number } {
  const [a, b] = ellipse.axes;
  const theta = (ellipse.angle_deg * Math.PI) / 180;
  const cos = Math.abs(Math.cos(theta));
  const sin = Math.abs(Math.sin(theta));
  return { x: Math.hypot(a * cos, b * sin), y: Math.hypot(a * sin, b * cos) };
}

/** The frame around the friend at `friend`, given their 95 % region (or none). */
export function answerFrame(friend: Point, region: Ellipse | null, photo: Size): Frame {
  const least = personSize(photo);
  const usable = region !== null && [...region.axes, ...region.center].every(Number.isFinite);
  if (!usable) return { centre: friend, half: { x: least, y: least }, outlined: false, sure: false, region: null };
  const reach = ellipseReach(region);
  return {
    centre: friend,
    // A little room around the region, as the server's drawing leaves.
    half: { x: Math.max(least, 1.1 * reach.x), y: Math.max(least, 1.1 * reach.y) },
    outlined: Math.min(...region.axes) >= OUTLINED_REGION * least,
    sure: true,
    region,
  };
}

/** Whether `p` lies inside `ellipse` (its boundary included). */
export function insideEllipse(p: Point, ellipse: Ellipse): boolean {
  const [a, b] = ellipse.axes;
  const theta = (ellipse.angle_deg * Math.PI) / 180;
  const dx = p.x - ellipse.center[0];
  const dy = p.y - ellipse.center[1];
  const along = Math.cos(theta) * dx + Math.sin(theta) * dy;
  const across = -Math.sin(theta) * dx + Math.cos(theta) * dy;
  return (along / a) ** 2 + (across / b) ** 2 <= 1;
}

/** A frame's box on screen (CSS px), never smaller than {@link MIN_FRAME_CSS} each way. */
export function screenFrame(frame: Frame, t: ViewTransform): { centre: Point; half: { x: number; y: number } } {
  return {
    centre: { x: t.tx + t.scale * frame.centre.x, y: t.ty + t.scale * frame.centre.y },
    half: {
      x: Math.max(MIN_FRAME_CSS, t.scale * frame.half.x),
      y: Math.max(MIN_FRAME_CSS, t.scale * frame.half.y),
    },
  };
}

/**
 * The four corner brackets of a box as an SVG path ("M ... L ... L ..." per corner: each an
 * L whose arms point inwards), its arms {@link BRACKET_ARM} of the shorter half-side.
 */
export function bracketPath(centre: Point, half: { x: number; y: number }): string {
  const arm = BRACKET_ARM * Math.min(half.x, half.y);
  const parts: string[] = [];
  for (const sx of [-1, 1]) {
    for (const sy of [-1, 1]) {
      const x = centre.x + sx * half.x;
      const y = centre.y + sy * half.y;
      parts.push(`M${r(x)} ${r(y - sy * arm)}L${r(x)} ${r(y)}L${r(x - sx * arm)} ${r(y)}`);
    }
  }
  return parts.join("");
}

function r(value: number): string {
  return value.toFixed(1);
}

/**
 * Points on the conic (x, y, 1) C (x, y, 1)^T = 0 inside the photo, where it crosses
 * every `step`-th pixel column and row (as the server draws it: a parametrisation could run
 * off to infinity; crossings handle ellipses, parabolas, both branches of a hyperbola and
 * line pairs alike). `conic` is the 3x3 symmetric matrix, row by row.
 */
export function conicPoints(conic: ReadonlyArray<readonly number[]>, photo: Size, step: number): Point[] {
  const c = (i: number, j: number): number => conic[i]?.[j] ?? 0;
  const points: Point[] = [];
  // Along a column x: A y^2 + B y + C = 0, and the same along a row, with x and y swapped.
  const roots = (a: number, b: number, k: number): number[] => {
    if (Math.abs(a) < 1e-12) return Math.abs(b) < 1e-12 ? [] : [-k / b];
    const disc = b * b - 4 * a * k;
    if (disc < 0) return [];
    const root = Math.sqrt(disc);
    return [(-b - root) / (2 * a), (-b + root) / (2 * a)];
  };
  const s = Math.max(1, step);
  for (let x = 0; x <= photo.width; x += s) {
    const a = c(1, 1);
    const b = 2 * (c(0, 1) * x + c(1, 2));
    const k = c(0, 0) * x * x + 2 * c(0, 2) * x + c(2, 2);
    for (const y of roots(a, b, k)) if (y >= 0 && y <= photo.height) points.push({ x, y });
  }
  for (let y = 0; y <= photo.height; y += s) {
    const a = c(0, 0);
    const b = 2 * (c(0, 1) * y + c(0, 2));
    const k = c(1, 1) * y * y + 2 * c(1, 2) * y + c(2, 2);
    for (const x of roots(a, b, k)) if (x >= 0 && x <= photo.width) points.push({ x, y });
  }
  return points;
}

/**
 * Where the arrow to a point out of sight goes: on the border of `box` (inset by `inset`),
 * on the ray from the box's centre towards `target`, with the ray's direction (radians, 0
 * along x, y down). Null when `target` is inside the box.
 */
export function edgeArrow(
  target: Point,
  box: { left: number; top: number; right: number; bottom: number },
  inset: number,
): { at: Point; angle: number } | null {
  if (target.x >= box.left && target.x <= box.right && target.y >= box.top && target.y <= box.bottom) return null;
  const centre = { x: (box.left + box.right) / 2, y: (box.top + box.bottom) / 2 };
  const dx = target.x - centre.x;
  const dy = target.y - centre.y;
  const halfW = Math.max(1, (box.right - box.left) / 2 - inset);
  const halfH = Math.max(1, (box.bottom - box.top) / 2 - inset);
  // The ray leaves the inset box where the first of its two slabs ends.
  const t = Math.min(dx === 0 ? Infinity : halfW / Math.abs(dx), dy === 0 ? Infinity : halfH / Math.abs(dy));
  return { at: { x: centre.x + t * dx, y: centre.y + t * dy }, angle: Math.atan2(dy, dx) };
}
