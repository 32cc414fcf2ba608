/**
 * What fingers (and a mouse) do on the photo, as a pure state machine.
 *
 * One finger: press shows the loupe, drag adjusts, release places the mark where the
 * finger is. A press on a landmark's number label grabs that landmark: drag moves it,
 * release without moving selects it. Two fingers: pinch zooms about their midpoint and
 * moving them pans; nothing is placed, also not when the fingers lift one by one.
 * A mouse: click places, drag pans (when zoomed), the wheel zooms.
 *
 * Points are screen points relative to the view (see viewTransform); {@link editOf} turns
 * what a lift does into photo pixels. The events come in through pointers.ts.
 */

import { tapSigma, type Aim } from "./precision";
import type { Tap } from "./session";
import {
  NO_INSETS,
  isInsidePhoto,
  panBy,
  pinchTransform,
  toPhoto,
  type Insets,
  type Point,
  type Size,
  type ViewTransform,
} from "./viewTransform";

/** A finger that moved less than this (screen px) is a tap for a mouse, a pan threshold. */
export const MOUSE_SLOP = 4;
/** A grabbed landmark that moved less than this was only tapped (selected). */
export const TOUCH_SLOP = 6;
/** A finger held this long (ms) before it lifts had time to aim with the loupe. */
export const LOUPE_AIM_MS = 500;
/** A finger held still this long (ms) brings the loupe; one that slides brings it at once.
 * A quick tap (about 100 ms) never draws it: on a phone slowed 4x, drawing the loupe on
 * every touch was most of a tap's time to the screen (docs/slow-phone.md). */
export const LOUPE_SHOW_MS = 150;

export interface Grab {
  /** The landmark's number. */
  readonly id: number;
  /** Where the landmark was on screen when grabbed. */
  readonly from: Point;
}

export type Gesture =
  | { readonly kind: "idle" }
  | {
      readonly kind: "press";
      readonly finger: number;
      readonly start: Point;
      readonly at: Point;
      readonly grab: Grab | null;
      readonly moved: boolean;
      readonly mouse: boolean;
      /** When the finger went down, ms (any clock: only differences count). */
      readonly since: number;
    }
  | {
      readonly kind: "pinch";
      readonly fingers: readonly [number, number];
      readonly from: readonly [Point, Point];
      readonly start: ViewTransform;
    }
  | { readonly kind: "pan"; readonly finger: number; readonly last: Point }
  /** Fingers still down after a pinch: nothing happens until all are up. */
  | { readonly kind: "done" };

export type Outcome =
  | { readonly kind: "none" }
  | { readonly kind: "place"; readonly at: Point; readonly aim: Aim }
  | { readonly kind: "move"; readonly id: number; readonly to: Point; readonly aim: Aim }
  | { readonly kind: "select"; readonly id: number };

export const IDLE: Gesture = { kind: "idle" };
const NOTHING: Outcome = { kind: "none" };

/** The fingers on the view: id -> screen point. */
export type Fingers = ReadonlyMap<number, Point>;

function distance(a: Point, b: Point): number {
  return Math.hypot(a.x - b.x, a.y - b.y);
}

/**
 * A finger (or the mouse button) went down at `at`; `grab`: it landed on a landmark's label;
 * `now`: the time, ms.
 */
export function fingerDown(
  gesture: Gesture,
  fingers: Fingers,
  finger: number,
  grab: Grab | null,
  transform: ViewTransform,
  mouse = false,
  now = 0,
): Gesture {
  if (gesture.kind === "done" || gesture.kind === "pinch") return gesture;
  if (fingers.size >= 2) {
    // A second finger: whatever one finger was doing is dropped; pinch with the first two.
    const [a, b] = [...fingers.entries()];
    if (!a || !b) return gesture;
    return { kind: "pinch", fingers: [a[0], b[0]], from: [a[1], b[1]], start: transform };
  }
  const at = fingers.get(finger);
  if (!at || gesture.kind !== "idle") return gesture;
  return { kind: "press", finger, start: at, at, grab, moved: false, mouse, since: now };
}

/** Fingers moved; returns the gesture and, for a pinch or pan, the new transform. */
export function fingersMove(
  gesture: Gesture,
  fingers: Fingers,
  transform: ViewTransform,
  view: Size,
  photo: Size,
  zoomed: boolean,
  slack: Insets = NO_INSETS,
): { gesture: Gesture; transform: ViewTransform | null } {
  switch (gesture.kind) {
    case "press": {
      const at = fingers.get(gesture.finger);
      if (!at) return { gesture, transform: null };
      const slop = gesture.mouse ? MOUSE_SLOP : TOUCH_SLOP;
      const moved = gesture.moved || distance(at, gesture.start) > slop;
      if (gesture.mouse && moved && !gesture.grab) {
        // A mouse drag pans (when zoomed); it never places.
        if (!zoomed) return { gesture: { kind: "pan", finger: gesture.finger, last: at }, transform: null };
        const panned = panBy(transform, at.x - gesture.start.x, at.y - gesture.start.y, view, photo, slack);
        return { gesture: { kind: "pan", finger: gesture.finger, last: at }, transform: panned };
      }
      return { gesture: { ...gesture, at, moved }, transform: null };
    }
    case "pinch": {
      const a = fingers.get(gesture.fingers[0]);
      const b = fingers.get(gesture.fingers[1]);
      if (!a || !b) return { gesture, transform: null };
      return { gesture, transform: pinchTransform(gesture.start, gesture.from, [a, b], view, photo, slack) };
    }
    case "pan": {
      const at = fingers.get(gesture.finger);
      if (!at) return { gesture, transform: null };
      const panned = zoomed ? panBy(transform, at.x - gesture.last.x, at.y - gesture.last.y, view, photo, slack) : null;
      return { gesture: { ...gesture, last: at }, transform: panned };
    }
    default:
      return { gesture, transform: null };
  }
}

/**
 * Finger `finger` lifted at `now` (ms; `cancelled`: the system took the touch away);
 * `fingers` are those still down. Returns the next gesture and what the lift does.
 */
export function fingerUp(
  gesture: Gesture,
  fingers: Fingers,
  finger: number,
  cancelled = false,
  now = 0,
): { gesture: Gesture; outcome: Outcome } {
  const next: Gesture = fingers.size > 0 ? { kind: "done" } : IDLE;
  switch (gesture.kind) {
    case "press": {
      if (finger !== gesture.finger) return { gesture, outcome: NOTHING };
      if (cancelled) return { gesture: next, outcome: NOTHING };
      const target = pressTarget(gesture);
      const aim = aimOf(gesture, now);
      if (gesture.grab) {
        const outcome: Outcome = gesture.moved
          ? { kind: "move", id: gesture.grab.id, to: target, aim }
          : { kind: "select", id: gesture.grab.id };
        return { gesture: next, outcome };
      }
      return { gesture: next, outcome: { kind: "place", at: target, aim } };
    }
    case "pinch":
    case "done":
      return { gesture: next, outcome: NOTHING };
    case "pan":
      return { gesture: finger === gesture.finger ? next : gesture, outcome: NOTHING };
    case "idle":
      return { gesture: IDLE, outcome: NOTHING };
  }
}

/**
 * How a press lifted at `now` was aimed: with the loupe when the finger slid under it or
 * was held long enough to look at it, else as a quick tap of the finger. A mouse's pointer
 * is as precise as the loupe's cross-hair.
 */
function aimOf(press: Extract<Gesture, { kind: "press" }>, now: number): Aim {
  if (press.mouse || press.moved) return "loupe";
  return now - press.since >= LOUPE_AIM_MS ? "loupe" : "finger";
}

/**
 * Where a press points (screen): the finger itself, or for a grabbed landmark where the
 * landmark has been dragged to (it moves with the finger, from where it was).
 */
export function pressTarget(gesture: Extract<Gesture, { kind: "press" }>): Point {
  if (!gesture.grab) return gesture.at;
  return {
    x: gesture.grab.from.x + gesture.at.x - gesture.start.x,
    y: gesture.grab.from.y + gesture.at.y - gesture.start.y,
  };
}

/** The point the loupe magnifies, while a finger is pressing; null otherwise. */
export function loupeTarget(gesture: Gesture): Point | null {
  return gesture.kind === "press" && !gesture.mouse ? pressTarget(gesture) : null;
}

/** The wheel's zoom factor for one wheel event (deltaY in px; up zooms in). */
export function wheelFactor(deltaY: number, deltaMode = 0): number {
  const pixels = deltaMode === 1 ? deltaY * 16 : deltaMode === 2 ? deltaY * 400 : deltaY;
  return Math.exp(-Math.max(-300, Math.min(300, pixels)) * 0.002);
}

/** What a lift does to this phone's marks, in photo px. */
export type Edit =
  | { readonly kind: "place"; readonly tap: Tap }
  | { readonly kind: "move"; readonly id: number; readonly tap: Tap }
  | { readonly kind: "select"; readonly id: number };

/**
 * The edit an outcome makes at transform `t`, each tap with its precision at the zoom and aim
 * it was made with; null: none (nothing happened, or a tap beside the photo). A landmark
 * dragged off the photo stays on its edge.
 */
export function editOf(outcome: Outcome, t: ViewTransform, photo: Size): Edit | null {
  switch (outcome.kind) {
    case "place": {
      const at = toPhoto(t, outcome.at);
      return isInsidePhoto(at, photo) ? { kind: "place", tap: { ...at, sigma: tapSigma(t.scale, outcome.aim) } } : null;
    }
    case "move": {
      const at = toPhoto(t, outcome.to);
      const tap = {
        x: Math.min(Math.max(at.x, 0), photo.width),
        y: Math.min(Math.max(at.y, 0), photo.height),
        sigma: tapSigma(t.scale, outcome.aim),
      };
      return { kind: "move", id: outcome.id, tap };
    }
    case "select":
      return { kind: "select", id: outcome.id };
    case "none":
      return null;
  }
}
