/**
 * What "Show me" says, in the app's words (answer.ts): where the friend is in the live view,
 * which way to turn, and what to do when the view is not anchored to the photo.
 */

import type { Pointing } from "./pointer";

export const FRAME_LIVE_TEXT = "Your friend is inside the yellow frame marked \u201cfriend\u201d.";
export const CURVE_LIVE_TEXT = "Your friend is somewhere on the dotted yellow curve.";
export const ALIGN_TEXT =
  "Stand where you took your photo, hold the phone as you took it, and tap Align.";
export const ALIGNING_TEXT = "Matching the view to your photo...";
export const NOT_MATCHED_TEXT =
  "The view did not match your photo. Hold the phone as you took it, where you stood, and tap Align again.";
export const ALIGN_UNAVAILABLE_TEXT = "The view cannot be matched to your photo right now: try again later.";
export const NO_MOTION_TEXT = "Motion access is off: the view cannot follow the phone.";
export const NO_SENSOR_TEXT = "Waiting for the phone to say how it is turned...";
export const HOLD_STILL_TEXT = "Hold still...";
export const DRIFT_TEXT = "The pointer may have drifted: hold the phone toward the stage and tap Re-align.";
export const MOVED_TEXT =
  "You have moved: the pointer assumes you stand where you took the photo. Go back there, or take a new photo.";
export const STAY_TEXT = "Stay where you took the photo: the marker follows your turns, not your steps.";

/** The main sentence for where the friend is (null: the marker says nothing by itself, or
 * the curve is on the screen); `curve`: the answer is a curve alone, no point. */
export function pointingText(pointing: Pointing | null, curve: boolean): string {
  if (!pointing) return curve ? CURVE_LIVE_TEXT : "";
  if (pointing.kind === "in-view") return FRAME_LIVE_TEXT;
  if (curve) return `Turn ${pointing.turn}: the dotted curve your friend is on is that way.`;
  return `Turn ${pointing.turn}: your friend is that way.`;
}

/** The words on the arrow at the edge. */
export function arrowLabel(pointing: Pointing): string {
  return pointing.kind === "off-view" ? `turn ${pointing.turn}` : "";
}
