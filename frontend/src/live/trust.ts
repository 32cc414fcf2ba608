/**
 * When "Show me"'s pointing is no longer to be trusted: the orientation has run for long
 * since the last anchor (the gyroscope drifts), or the phone has walked away from where it
 * took its photo (the view follows turns only, pointer.ts).
 *
 * Drift: DRIFT_MS after the anchor (the shutter, or an Align), the view says so. A good
 * phone's fused orientation drifts well under a degree in that time, a poor one's (10-20
 * degrees per hour of gyroscope bias) a few tenths of a degree a minute: two minutes is where
 * a person 50 m off may be a person further along.
 *
 * Movement: steps. `devicemotion`'s `acceleration` (gravity removed by the phone) read along
 * the vertical (which way is up: `accelerationIncludingGravity` less `acceleration`): a
 * walking person's body rises and falls once a step, about 2 a second, 1-3 m/s^2 each
 * time, while a hand's shake is a few tenths and turning on the spot accelerates the phone
 * sideways (round the body), not up and down. A step is the vertical acceleration, smoothed
 * over SMOOTH_MS, rising above STEP_HIGH and falling back below STEP_LOW; STEPS_TO_WARN
 * steps in a row, each within STEP_GAP_MS of the last (a pace), are a walk. Where the phone
 * gives no `acceleration` (some Android browsers), |accelerationIncludingGravity| less g is
 * the same vertical signal, as the sideways part adds to it only to second order. The
 * signals are integrated no further (position from a phone's accelerometer drifts metres in
 * seconds): a walk is said, not measured.
 */

/** A reading of the phone's motion, m/s^2 in the device's frame; `at` ms. */
export interface MotionReading {
  at: number;
  /** Without gravity (null where the phone does not give it). */
  acceleration: readonly [number, number, number] | null;
  /** With gravity (pointing up at rest). */
  includingGravity: readonly [number, number, number] | null;
}

/** How long after the anchor the view says it may have drifted, ms. */
export const DRIFT_MS = 120_000;
/** The vertical acceleration's smoothing (an exponential time constant), ms: a hand's
 * 8-12 Hz shake is damped, a step's 2 Hz is not. */
export const SMOOTH_MS = 40;
/** A step: the smoothed vertical acceleration above this, m/s^2... */
export const STEP_HIGH = 0.8;
/** ...and back below this before the next one counts. */
export const STEP_LOW = 0.3;
/** Steps in a row, each within STEP_GAP_MS of the last, that make a walk (3-4 m). */
export const STEPS_TO_WARN = 4;
export const STEP_GAP_MS = 1200;
/** Readings further apart than this (a page the browser paused) start the count again. */
export const MAX_READING_GAP_MS = 500;
const GRAVITY = 9.80665;

/** Whether the view has run long enough since its anchor (`anchoredAt`, ms) to drift. */
export function mayHaveDrifted(anchoredAt: number, now: number): boolean {
  return now - anchoredAt >= DRIFT_MS;
}

function norm(v: readonly number[]): number {
  return Math.hypot(v[0] ?? 0, v[1] ?? 0, v[2] ?? 0);
}

/** The vertical acceleration of one reading (up positive), or null if it says nothing. */
export function verticalAcceleration(reading: MotionReading): number | null {
  const { acceleration: a, includingGravity: g } = reading;
  if (a && g) {
    const up: [number, number, number] = [g[0] - a[0], g[1] - a[1], g[2] - a[2]];
    const length = norm(up);
    if (length > GRAVITY / 2) return (a[0] * up[0] + a[1] * up[1] + a[2] * up[2]) / length;
  }
  if (g) return norm(g) - GRAVITY;
  // Only the linear acceleration: its size (a shake counts too, a turn's sideways pull too).
  if (a) return norm(a);
  return null;
}

/** Counts the steps in the readings given to it, oldest first; says when they make a walk. */
export class StepWatch {
  private smooth = 0;
  private last: number | null = null;
  private rising = false;
  private lastStep: number | null = null;
  private run = 0;
  /** Steps in the current pace. */
  get steps(): number {
    return this.run;
  }
  /** Set once a walk is seen, until reset(). */
  moved = false;

  push(reading: MotionReading): void {
    const v = verticalAcceleration(reading);
    if (v === null || !Number.isFinite(v)) return;
    const gap = this.last === null ? Number.POSITIVE_INFINITY : reading.at - this.last;
    if (gap <= 0) return;
    if (gap > MAX_READING_GAP_MS) {
      this.smooth = v;
      this.rising = false;
      this.run = 0;
      this.lastStep = null;
    } else {
      this.smooth += (1 - Math.exp(-gap / SMOOTH_MS)) * (v - this.smooth);
    }
    this.last = reading.at;
    if (!this.rising && this.smooth > STEP_HIGH) {
      this.rising = true;
      const paced = this.lastStep !== null && reading.at - this.lastStep <= STEP_GAP_MS;
      this.run = paced ? this.run + 1 : 1;
      this.lastStep = reading.at;
      if (this.run >= STEPS_TO_WARN) this.moved = true;
    } else if (this.rising && this.smooth < STEP_LOW) {
      this.rising = false;
    }
  }

  /** A new anchor: the phone stands where it is now. */
  reset(): void {
    this.moved = false;
    this.run = 0;
    this.lastStep = null;
  }
}

/** A `devicemotion` event as a reading (null: the event carries no acceleration). */
export function motionReading(event: DeviceMotionEvent, at: number): MotionReading | null {
  const vector = (v: DeviceMotionEventAcceleration | null | undefined): [number, number, number] | null =>
    v && v.x != null && v.y != null && v.z != null ? [v.x, v.y, v.z] : null;
  const acceleration = vector(event.acceleration);
  const includingGravity = vector(event.accelerationIncludingGravity);
  return acceleration || includingGravity ? { at, acceleration, includingGravity } : null;
}
