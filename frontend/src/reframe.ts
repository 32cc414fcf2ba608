/**
 * Bringing the answer into view: when it first arrives, or moves noticeably, the view
 * glides to show it with some room around it (unless the person is in the middle of a
 * gesture: then it waits); when it is out of sight, an arrow at the view's edge points to
 * it (`edgeArrow`).
 */

import {
  clampTransform,
  fitTransform,
  isInsidePhoto,
  scaleLimits,
  toPhoto,
  type Point,
  type Insets,
  type Size,
  type ViewTransform,
} from "./viewTransform";

/** A box in photo px: its centre and half-sizes. */
export interface Box {
  centre: Point;
  half: { x: number; y: number };
}

export type { Insets } from "./viewTransform";

/** Room around the answer when the view reframes: the box shown this many times its size. */
export const CONTEXT = 4;
/** How long the glide to the answer lasts, ms. */
export const GLIDE_MS = 450;

/** The part of the view that is not covered, in screen px. */
export function clearArea(view: Size, insets: Insets): { left: number; top: number; right: number; bottom: number } {
  return {
    left: insets.left,
    top: insets.top,
    right: Math.max(insets.left + 1, view.width - insets.right),
    bottom: Math.max(insets.top + 1, view.height - insets.bottom),
  };
}

/** Whether the whole box is in the clear part of the view at `t`. */
export function boxInView(box: Box, t: ViewTransform, view: Size, insets: Insets): boolean {
  const area = clearArea(view, insets);
  const left = t.tx + t.scale * (box.centre.x - box.half.x);
  const right = t.tx + t.scale * (box.centre.x + box.half.x);
  const top = t.ty + t.scale * (box.centre.y - box.half.y);
  const bottom = t.ty + t.scale * (box.centre.y + box.half.y);
  return left >= area.left && right <= area.right && top >= area.top && bottom <= area.bottom;
}

/**
 * Where the view should go to show `box` (clipped to the photo) with room around it, or
 * null when it is already in view at `current`. It zooms out as far as needed to fit
 * {@link CONTEXT} times the box in the clear area, never in further than `current`.
 */
export function frameTarget(box: Box, current: ViewTransform, view: Size, photo: Size, insets: Insets): ViewTransform | null {
  const clipped = shownPart(box, photo);
  const reach = overhang(clipped, photo);
  if (boxInView(clipped, current, view, insets)) return null;
  const area = clearArea(view, insets);
  const width = area.right - area.left;
  const height = area.bottom - area.top;
  const fits = Math.min(width / (2 * CONTEXT * clipped.half.x), height / (2 * CONTEXT * clipped.half.y));
  const fitted = fitTransform(view, photo).scale;
  const chosen = Math.max(fitted, Math.min(current.scale, fits));
  // The box's centre in the middle of the clear area, not of the whole view; the photo's
  // edge may come in as far as the covered bands (clampTransform), not past them.
  const middle = { x: (area.left + area.right) / 2, y: (area.top + area.bottom) / 2 };
  const at = (scale: number): ViewTransform =>
    clampTransform(
      { scale, tx: middle.x - clipped.centre.x * scale, ty: middle.y - clipped.centre.y * scale },
      view,
      photo,
      slackFor(insets, reach, scale),
    );
  // When that is not enough (a box wider than the clear area at this zoom), zoom in a
  // little further, as far as the box still fits.
  const most = Math.max(chosen, Math.min(CONTEXT * fits, scaleLimits(view, photo).max));
  for (let scale = chosen; scale <= most; scale *= 1.25) {
    const candidate = at(scale);
    if (boxInView(clipped, candidate, view, insets)) return candidate;
  }
  return at(chosen);
}

/**
 * What of the answer's box the view must show: all of it when its centre is on the photo
 * (its frame is drawn whole, past the photo's edge too), else its part on the photo.
 */
export function shownPart(box: Box, photo: Size): Box {
  return isInsidePhoto(box.centre, photo) ? box : clipToPhoto(box, photo);
}

/** How far `box` reaches past each of the photo's edges, photo px (0 where it does not). */
export function overhang(box: Box, photo: Size): Insets {
  return {
    top: Math.max(0, box.half.y - box.centre.y),
    right: Math.max(0, box.centre.x + box.half.x - photo.width),
    bottom: Math.max(0, box.centre.y + box.half.y - photo.height),
    left: Math.max(0, box.half.x - box.centre.x),
  };
}

/**
 * How far the photo's edge may come in from each side of the view at `scale`: as far as the
 * covered bands, and further by what of the answer's frame reaches past the photo (`reach`,
 * photo px), so that a frame at the photo's edge is shown whole, clear of the bands.
 */
export function slackFor(insets: Insets, reach: Insets, scale: number): Insets {
  return {
    top: insets.top + reach.top * scale,
    right: insets.right + reach.right * scale,
    bottom: insets.bottom + reach.bottom * scale,
    left: insets.left + reach.left * scale,
  };
}

/** The box's part on the photo; a box wholly off it shrinks to the nearest border point. */
export function clipToPhoto(box: Box, photo: Size): Box {
  const clamp = (v: number, low: number, high: number): number => Math.min(Math.max(v, low), high);
  const x0 = clamp(box.centre.x - box.half.x, 0, photo.width);
  const x1 = clamp(box.centre.x + box.half.x, 0, photo.width);
  const y0 = clamp(box.centre.y - box.half.y, 0, photo.height);
  const y1 = clamp(box.centre.y + box.half.y, 0, photo.height);
  // Half-sizes of at least 1 px: a box squeezed onto a border still has a size to fit.
  return {
    centre: { x: (x0 + x1) / 2, y: (y0 + y1) / 2 },
    half: { x: Math.max(1, (x1 - x0) / 2), y: Math.max(1, (y1 - y0) / 2) },
  };
}

/**
 * Whether the answer moved noticeably from `before` to `after` (a new answer, or its centre
 * moved out of the old frame): the view reframes then, not for every small refinement.
 */
export function movedNoticeably(before: Box | null, after: Box): boolean {
  if (!before) return true;
  return (
    Math.abs(after.centre.x - before.centre.x) > before.half.x ||
    Math.abs(after.centre.y - before.centre.y) > before.half.y
  );
}

/**
 * The view `k` of the way (0..1) from `from` to `to`: the photo point in the middle of the
 * view moves in a straight line while the scale changes geometrically (a steady zoom).
 */
export function glide(from: ViewTransform, to: ViewTransform, k: number, view: Size): ViewTransform {
  const middle = { x: view.width / 2, y: view.height / 2 };
  const a = toPhoto(from, middle);
  const b = toPhoto(to, middle);
  const scale = from.scale * Math.pow(to.scale / from.scale, k);
  const at = { x: a.x + (b.x - a.x) * k, y: a.y + (b.y - a.y) * k };
  return { scale, tx: middle.x - at.x * scale, ty: middle.y - at.y * scale };
}

/** Ease in and out: slow at both ends (a smooth glide). */
export function easeInOut(k: number): number {
  const c = Math.min(Math.max(k, 0), 1);
  return c * c * (3 - 2 * c);
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
