/**
 * A still frame for Align and Re-align: the frame sent to be matched is taken when the phone
 * holds still, not at the tap. A turning phone blurs its frame (a 15 px motion blur is
 * matched only by the server's second, coarser try: make bench-reanchor), and the orientation
 * paired with the frame is only as good as the moment they share.
 *
 * Still: the phone turned less than STILL_RATE_DEG_S over the last STILL_SPAN_MS, read from
 * the view's own orientation readings (sensor.ts; a reading holds until the next, so the one
 * in force when the span opened counts). The view waits up to STILL_WAIT_MS for that,
 * saying "Hold still..."; meanwhile it keeps the stillest frame seen, and sends that one if
 * the phone never holds still.
 */

import { multiply, rotationAngleDeg, transpose } from "./orientation";
import type { Sample } from "./sensor";

/** Still: turning slower than this, degrees a second... */
export const STILL_RATE_DEG_S = 3;
/** ...over this long, ms. */
export const STILL_SPAN_MS = 300;
/** How long Align waits for a still phone before sending its stillest frame, ms. */
export const STILL_WAIT_MS = 1500;

/**
 * How fast the phone turned over the `spanMs` before `now`: the greatest angle between the
 * newest reading and any reading in force in the span, over the span (degrees a second), or
 * null with no reading.
 */
export function turnRate(samples: readonly Sample[], now: number, spanMs = STILL_SPAN_MS): number | null {
  const before = samples.filter((s) => s.at <= now);
  const newest = before[before.length - 1];
  if (!newest) return null;
  let first = 0;
  before.forEach((s, i) => {
    if (s.at <= now - spanMs) first = i;
  });
  const spread = Math.max(0, ...before.slice(first).map((s) => rotationAngleDeg(multiply(transpose(s.device), newest.device))));
  return spread / (spanMs / 1000);
}

/**
 * What to do with the frame of the moment while waiting for a still phone: "send" it (the
 * phone is still, or it is the stillest yet when the wait is over), "keep" it as the
 * stillest so far, "wait" for the next, or send the "best" frame kept (the wait is over).
 */
export type Look = "send" | "keep" | "wait" | "best";

export class StillWait {
  private least = Number.POSITIVE_INFINITY;

  constructor(
    private readonly start: number,
    private readonly waitMs = STILL_WAIT_MS,
  ) {}

  /** The phone turning at `rate` (degrees a second; null: unknown) at `now`, ms. */
  look(now: number, rate: number | null): Look {
    const known = rate ?? Number.POSITIVE_INFINITY;
    if (known < STILL_RATE_DEG_S) return "send";
    const stillest = known < this.least;
    if (stillest) this.least = known;
    if (now - this.start >= this.waitMs) return stillest || this.least === Number.POSITIVE_INFINITY ? "send" : "best";
    return stillest ? "keep" : "wait";
  }

  /** The rate of the stillest frame kept (degrees a second), or null. */
  get stillest(): number | null {
    return Number.isFinite(this.least) ? this.least : null;
  }
}
