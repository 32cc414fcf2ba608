/**
 * The phone's orientation at the in-app camera's shutter, kept on the phone with the photo
 * for "Show me" (the server never has it): the anchor A = D C of orientation.ts.
 *
 * Read as down is (camera/gravity.ts): over the last STILL_WINDOW_MS before the tap, and
 * only if the phone held still then (no two readings in force in the window more than
 * MOVING_SPREAD_DEG apart); a moving phone keeps none, and "Show me" then aligns on a frame.
 * The sensor runs only while the camera is open (PhotoStep.tsx starts and stops it;
 * InAppCamera.tsx marks the shutter), and only with motion access granted.
 */

import { MOVING_SPREAD_DEG, STILL_WINDOW_MS } from "../camera/gravity";
import { motionAccess } from "../camera/motion";
import { anchorAt, multiply, rotationAngleDeg, transpose, type Matrix3 } from "./orientation";
import { OrientationSource, type Sample } from "./sensor";

/**
 * The reading at the shutter (time `now`, ms), or null when there is none or the phone
 * turned in the window. A reading holds until the next (a browser sends one only when the
 * orientation changes), so the one in force when the window opened counts too.
 */
export function stillOrientation(samples: readonly Sample[], now: number): Sample | null {
  const before = samples.filter((s) => s.at <= now);
  const start = now - STILL_WINDOW_MS;
  let first = 0;
  before.forEach((s, i) => {
    if (s.at <= start) first = i;
  });
  const inForce = before.slice(first);
  const newest = inForce[inForce.length - 1];
  if (!newest) return null;
  const turned = inForce.some((s) => rotationAngleDeg(multiply(transpose(s.device), newest.device)) > MOVING_SPREAD_DEG);
  return turned ? null : newest;
}

let source: OrientationSource | null = null;
let marked: Matrix3 | null = null;
let markedAt: number | null = null;
let takenAt: number | null = null;

/** The camera opened: the orientation is read until stop(). */
export function startShutterOrientation(): void {
  source?.stop();
  marked = null;
  source = new OrientationSource(undefined, 2 * STILL_WINDOW_MS);
  source.start();
}

/** The shutter was tapped: the anchor now, if the phone was still and motion is allowed. */
export function markShutter(): void {
  const reading = source && motionAccess() === "granted" ? stillOrientation(source.readings(), performance.now()) : null;
  marked = reading ? anchorAt(reading) : null;
  markedAt = reading ? performance.now() : null;
}

/** The anchor of the photo just taken (once), or null. */
export function takeShutterAnchor(): Matrix3 | null {
  const anchor = marked;
  if (anchor) takenAt = markedAt;
  marked = null;
  return anchor;
}

/** When (performance.now(), ms) the last anchor taken was read: the drift runs from then. */
export function lastShutterTime(): number | null {
  return takenAt;
}

/** The camera closed: no sensor is read. */
export function stopShutterOrientation(): void {
  source?.stop();
  source = null;
}
