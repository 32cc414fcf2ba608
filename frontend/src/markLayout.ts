/**
 * Where the marks' labels and the loupe go on screen, so that neither hides the spot being
 * tapped: a landmark's number sits beside its point (the point itself stays visible), and
 * the loupe sits above the finger, or beside it near the top edge.
 */

import type { Point, Size } from "./viewTransform";

/** Distance (screen px, along x and y) from a landmark's point to its label's centre. */
export const LABEL_OFFSET = 18;
/** The loupe's side, screen px. */
export const LOUPE_SIZE = 132;
/** Gap between the finger and the loupe, screen px. */
export const LOUPE_GAP = 44;

/** Keep a label at least this far (screen px) from other points and labels, if it can be. */
export const LABEL_CLEARANCE = 30;

const DIAGONALS: ReadonlyArray<readonly [number, number]> = [
  [1, -1], // up and right first
  [-1, -1],
  [1, 1],
  [-1, 1],
];

/**
 * The centres of the landmarks' labels, beside their points: up and right where there is
 * room, else the diagonal farthest from the other points and the labels already placed
 * (so close landmarks keep readable numbers), always inside the view when possible.
 */
export function labelPositions(
  points: ReadonlyArray<{ id: number; at: Point }>,
  view: Size,
  others: readonly Point[] = [],
): Map<number, Point> {
  const placed = new Map<number, Point>();
  const half = 16;
  for (const { id, at } of points) {
    const obstacles = [
      ...points.filter((p) => p.id !== id).map((p) => p.at),
      ...others,
      ...placed.values(),
    ];
    let best: { at: Point; score: number } | null = null;
    for (const [dx, dy] of DIAGONALS) {
      const centre = { x: at.x + dx * LABEL_OFFSET, y: at.y + dy * LABEL_OFFSET };
      const inside =
        centre.x - half >= 0 && centre.y - half >= 0 && centre.x + half <= view.width && centre.y + half <= view.height;
      const clearance = Math.min(
        Infinity,
        ...obstacles.map((o) => Math.hypot(o.x - centre.x, o.y - centre.y)),
      );
      // Inside the view first; then clear of others; the first diagonal wins a tie.
      const score = (inside ? 2 : 0) + (clearance >= LABEL_CLEARANCE ? 1 : clearance / LABEL_CLEARANCE);
      if (!best || score > best.score + 1e-9) best = { at: centre, score };
      if (inside && clearance >= LABEL_CLEARANCE) break;
    }
    if (best) placed.set(id, best.at);
  }
  return placed;
}

/** The loupe's top-left corner for a finger at `finger` (screen px in the view). */
export function loupePosition(finger: Point, view: Size, size: number = LOUPE_SIZE): Point {
  const margin = 4;
  const clamp = (value: number, low: number, high: number): number =>
    Math.min(Math.max(value, low), Math.max(low, high));
  const above = finger.y - LOUPE_GAP - size;
  if (above >= margin) {
    return { x: clamp(finger.x - size / 2, margin, view.width - size - margin), y: above };
  }
  // Too close to the top: beside the finger, on the roomier side.
  const x = finger.x < view.width / 2 ? finger.x + LOUPE_GAP : finger.x - LOUPE_GAP - size;
  return {
    x: clamp(x, margin, view.width - size - margin),
    y: clamp(finger.y - size / 2, margin, view.height - size - margin),
  };
}

/** How much bigger the loupe shows the photo than the view does (screen px per photo px). */
export function loupeZoom(viewScale: number): number {
  return viewScale * (viewScale < 1.5 ? 3 : 2);
}
