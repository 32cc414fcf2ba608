/**
 * The live video's focal length, measured once each time the view opens anchored at the
 * in-app camera's shutter. Without it the video's is the photo's scaled by their long sides
 * (pointer.ts's liveFocal), which assumes the stream shows the whole sensor as the photo
 * does; a stream that crops or zooms further would put the marker off by the crop's share
 * of its distance from the centre. Align measures it, but a view anchored at the shutter
 * needs no Align, so the view checks on its own: the first time the phone holds still
 * (still.ts) turned less than CHECK_WITHIN_DEG from its photo's view, so that the frame
 * shows much of the photo, one frame goes to the server's matching (frames.ts).
 *
 * Only the focal length is taken, and only when the match's turn agrees with the sensors'
 * (within AGREE_DEG): the shutter's anchor is exact but for the gyroscope's drift, which a
 * match moves by its own error (about 0.1 degree), and a frame matched wrongly must move
 * nothing. A refusal, no connection or a disagreeing match leave the assumption in place,
 * and nothing is said: the person asked for nothing. Align still measures both.
 */

import { multiply, rotationAngleDeg, transpose, type Matrix3 } from "./orientation";
import { STILL_RATE_DEG_S } from "./still";

/** The check waits until the phone is turned less than this from its photo's view, degrees
 * (a phone facing a friend it saw in its photo turned less: the frame still shares a third
 * or more of its 50-65 degree wide view with the photo, which the server matches). */
export const CHECK_WITHIN_DEG = 30;
/** A match whose turn is further than this from the sensors' is not trusted, degrees: a
 * phone's fused orientation drifts well under it in the minutes a search takes. */
export const AGREE_DEG = 2;

/** Where the check is: not to be made (no shutter anchor, or an answer without a focal
 * length, which the server cannot match), waiting for a still phone facing its photo's
 * view, sent, or over (measured, refused, or a match that disagreed with the sensors). */
export type FocalCheck = "off" | "waiting" | "sending" | "measured" | "refused" | "disagreed";

/** Whether to send the check's frame now: waiting, the phone still (turn rate in degrees a
 * second, null when unknown) and turned less than CHECK_WITHIN_DEG since the shutter. */
export function checkNow(check: FocalCheck, rate: number | null, turnedDeg: number): boolean {
  return check === "waiting" && rate !== null && rate < STILL_RATE_DEG_S && turnedDeg < CHECK_WITHIN_DEG;
}

/** Whether the server's turn for the frame (`matched`) agrees with the sensors' turn since
 * the shutter at the frame's moment (`sensed`), both from the photo's camera frame. */
export function agrees(matched: Matrix3, sensed: Matrix3): boolean {
  return rotationAngleDeg(multiply(matched, transpose(sensed))) <= AGREE_DEG;
}
