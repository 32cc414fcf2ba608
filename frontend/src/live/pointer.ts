/**
 * The answer's drawing carried from the photo into the live camera view: a phone that stands
 * where it took its photo and turns sees the scene through a pure rotation R (orientation.ts),
 * so a photo pixel x appears in the video at H x with H = K_live R K_photo^-1 (a homography;
 * Hartley & Zisserman 8.4.2). Every point of the server's drawing goes through H: the live
 * view is the same drawing, turned (no answer geometry of the phone's own).
 *
 * Pixels: the photo's (x right, y down, principal point at its centre), the video's (the
 * same, of the live stream's frames), and the screen's (CSS px of the view that shows the
 * video with object-fit: cover, which crops the video to the screen's shape).
 */

import type { Matrix3, Vector3 } from "./orientation";
import { multiply } from "./orientation";

export interface Size {
  width: number;
  height: number;
}

export interface Point {
  x: number;
  y: number;
}

/** The diagonal of a 36 x 24 mm film frame, mm: the reference of "35 mm equivalent". */
export const FILM_DIAGONAL_MM = Math.hypot(36, 24);

/** The photo's focal length in px from the 35 mm-equivalent the answer used (its diagonal
 * against a 36 x 24 mm frame's, as shared_solver.estimation.camera.focal_px). */
export function focalFrom35mm(focal35mm: number, size: Size): number {
  return (focal35mm / FILM_DIAGONAL_MM) * Math.hypot(size.width, size.height);
}

function longSide(size: Size): number {
  return Math.max(size.width, size.height);
}

/**
 * The live video's focal length, px. Measured when the server matched a frame of it to the
 * photo (`measuredPerLongSide`: the frame's focal over the frame's long side). Else the
 * photo's, scaled by the ratio of the long sides: this assumes the stream shows the whole
 * sensor width as the photo does (a 16:9 stream cropped from a 4:3 sensor keeps the long
 * side), which a stream that zooms or crops further breaks; re-anchoring measures it.
 */
export function liveFocal(photoFocal: number, photo: Size, video: Size, measuredPerLongSide: number | null = null): number {
  if (measuredPerLongSide !== null && measuredPerLongSide > 0) return measuredPerLongSide * longSide(video);
  return (photoFocal * longSide(video)) / longSide(photo);
}

function intrinsics(focal: number, size: Size): Matrix3 {
  return [
    [focal, 0, size.width / 2],
    [0, focal, size.height / 2],
    [0, 0, 1],
  ];
}

function inverseIntrinsics(focal: number, size: Size): Matrix3 {
  return [
    [1 / focal, 0, -size.width / (2 * focal)],
    [0, 1 / focal, -size.height / (2 * focal)],
    [0, 0, 1],
  ];
}

/** H = K_live R K_photo^-1: a photo pixel (homogeneous) into the live video's. */
export function homography(rotation: Matrix3, photoFocal: number, photo: Size, videoFocal: number, video: Size): Matrix3 {
  return multiply(multiply(intrinsics(videoFocal, video), rotation), inverseIntrinsics(photoFocal, photo));
}

/** H applied to a photo point, homogeneous: w is the depth along the live camera's axis
 * (over the photo's), so w <= 0 is behind the live camera. */
export function warp(h: Matrix3, p: Vector3): Vector3 {
  return [
    h[0][0] * p[0] + h[0][1] * p[1] + h[0][2] * p[2],
    h[1][0] * p[0] + h[1][1] * p[1] + h[1][2] * p[2],
    h[2][0] * p[0] + h[2][1] * p[1] + h[2][2] * p[2],
  ];
}

/** How the video is shown on a view of `box` CSS px with object-fit: cover: screen = video
 * px * scale + offset (the offsets are negative or zero: the cropped part). */
export interface Cover {
  scale: number;
  offset: Point;
  box: Size;
}

export function cover(video: Size, box: Size): Cover {
  const scale = Math.max(box.width / video.width, box.height / video.height);
  return {
    scale,
    offset: { x: (box.width - video.width * scale) / 2, y: (box.height - video.height * scale) / 2 },
    box,
  };
}

/** A homogeneous video point on the screen, or null behind the camera (w <= 0). */
export function onScreen(c: Cover, p: Vector3): Point | null {
  if (!(p[2] > 0)) return null;
  return { x: (p[0] / p[2]) * c.scale + c.offset.x, y: (p[1] / p[2]) * c.scale + c.offset.y };
}

/** A photo point all the way onto the screen (null: behind the live camera). */
export function photoToScreen(h: Matrix3, c: Cover, p: readonly number[]): Point | null {
  return onScreen(c, warp(h, [p[0] ?? Number.NaN, p[1] ?? Number.NaN, 1]));
}

/**
 * Polylines of photo px on the screen: each point through H, a line broken where it goes
 * behind the camera (no point behind is drawn, nor joined across).
 */
export function linesToScreen(h: Matrix3, c: Cover, lines: ReadonlyArray<ReadonlyArray<readonly number[]>>): Point[][] {
  const out: Point[][] = [];
  for (const line of lines) {
    let piece: Point[] = [];
    for (const p of line) {
      const s = photoToScreen(h, c, p);
      if (s) {
        piece.push(s);
      } else {
        if (piece.length > 1) out.push(piece);
        piece = [];
      }
    }
    if (piece.length > 1) out.push(piece);
  }
  return out;
}

export type Turn = "left" | "right" | "up" | "down";

/** Where the friend is for the live view: in the visible part of the video, or off it. */
export type Pointing =
  | { kind: "in-view"; at: Point }
  /** Off the screen (or behind the camera): an arrow at `at` on the screen's edge, pointing
   * `angle` (radians, screen: x right, y down), and which way to turn. */
  | { kind: "off-view"; at: Point; angle: number; turn: Turn };

/**
 * Where the friend (`friend`: the photo's homogeneous pixel, w < 0 behind the photo's
 * camera, as the answer's friend_h) is on the live screen. In view when inside the screen
 * less `inset` CSS px on each side (the visible rectangle of the cropped video); else an
 * arrow `inset` px inside the edge, on the ray from the screen's centre (the video's
 * principal point) towards them.
 */
export function pointAt(h: Matrix3, c: Cover, video: Size, friend: Vector3, inset: number): Pointing {
  const p = warp(h, friend);
  const seen = onScreen(c, p);
  const { width, height } = c.box;
  if (seen && seen.x >= inset && seen.x <= width - inset && seen.y >= inset && seen.y <= height - inset) {
    return { kind: "in-view", at: seen };
  }
  // The direction from the principal point on the screen: (x - cx w, y - cy w) is the
  // direction's (x, y) times the focal length, in front of the camera or behind it.
  const dx = p[0] - (video.width / 2) * p[2];
  const dy = p[1] - (video.height / 2) * p[2];
  const centre = { x: width / 2, y: height / 2 };
  const angle = Math.atan2(dy, dx);
  const reach = Math.min(
    Math.abs(dx) > 0 ? (width / 2 - inset) / Math.abs(Math.cos(angle)) : Number.POSITIVE_INFINITY,
    Math.abs(dy) > 0 ? (height / 2 - inset) / Math.abs(Math.sin(angle)) : Number.POSITIVE_INFINITY,
  );
  const at = { x: centre.x + reach * Math.cos(angle), y: centre.y + reach * Math.sin(angle) };
  const turn: Turn = Math.abs(dx) >= Math.abs(dy) ? (dx < 0 ? "left" : "right") : dy < 0 ? "up" : "down";
  return { kind: "off-view", at, angle, turn };
}

/** The screen px per photo px near the view's centre (the band's width goes by it). */
export function screenPerPhotoPx(c: Cover, photoFocal: number, videoFocal: number): number {
  return (c.scale * videoFocal) / photoFocal;
}

/** Pieces each segment of a curve is cut into when looking for its nearest part. */
const CURVE_SUBDIVISIONS = 8;

/** Whether the screen segment a-b meets the box [0, width] x [0, height] (Liang-Barsky). */
function meetsBox(a: Point, b: Point, box: Size): boolean {
  let [t0, t1] = [0, 1];
  const d = { x: b.x - a.x, y: b.y - a.y };
  const edges: [number, number][] = [
    [-d.x, a.x],
    [d.x, box.width - a.x],
    [-d.y, a.y],
    [d.y, box.height - a.y],
  ];
  for (const [p, q] of edges) {
    if (p === 0) {
      if (q < 0) return false;
      continue;
    }
    const t = q / p;
    if (p < 0) t0 = Math.max(t0, t);
    else t1 = Math.min(t1, t);
    if (t0 > t1) return false;
  }
  return true;
}

/**
 * Where the curve the friend is on (`lines`: the drawing's polylines, photo px) is for the
 * live view: null when some part of it is on the screen (it is drawn there), else an arrow
 * towards its nearest part, as for a friend (pointAt): the point of the curve whose
 * direction is the least angle from where the live camera looks (each segment cut into
 * CURVE_SUBDIVISIONS; `videoFocal` px), or null for a curve with no point.
 */
export function pointAtCurve(
  h: Matrix3,
  c: Cover,
  video: Size,
  videoFocal: number,
  lines: ReadonlyArray<ReadonlyArray<readonly number[]>>,
  inset: number,
): Pointing | null {
  const { width, height } = c.box;
  let nearest: Vector3 | null = null;
  let least = Number.POSITIVE_INFINITY;
  for (const line of lines) {
    let previous: Point | null = null;
    for (let i = 0; i < line.length; i += 1) {
      const [px, py] = [line[i]?.[0] ?? Number.NaN, line[i]?.[1] ?? Number.NaN];
      const next = line[i + 1];
      const [qx, qy] = next ? [next[0] ?? Number.NaN, next[1] ?? Number.NaN] : [px, py];
      const pieces = next ? CURVE_SUBDIVISIONS : 1;
      for (let k = 0; k < pieces; k += 1) {
        const t = k / pieces;
        const point: Vector3 = [px + t * (qx - px), py + t * (qy - py), 1];
        if (!Number.isFinite(point[0]) || !Number.isFinite(point[1])) continue;
        const w = warp(h, point);
        const seen = onScreen(c, w);
        if (seen && seen.x >= 0 && seen.x <= width && seen.y >= 0 && seen.y <= height) return null;
        if (seen && previous && meetsBox(previous, seen, c.box)) return null;
        previous = seen;
        // The angle from the live camera's axis: (x - cx w, y - cy w) over f, against w.
        const off = Math.hypot(w[0] - (video.width / 2) * w[2], w[1] - (video.height / 2) * w[2]) / videoFocal;
        const angle = Math.atan2(off, w[2]);
        if (angle < least) [least, nearest] = [angle, point];
      }
    }
  }
  return nearest ? pointAt(h, c, video, nearest, inset) : null;
}
