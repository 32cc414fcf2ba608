/**
 * Which way the lens looked at the shutter, from the phone's absolute orientation: its
 * heading, in degrees clockwise from north seen from above (north 0, east 90), of the lens
 * axis's horizontal direction. The solver uses only the difference of the two phones'
 * headings, so a magnetic north will do.
 *
 * The reading: `deviceorientationabsolute` (W3C DeviceOrientation Event; Chromium, Android):
 * `alpha`, `beta`, `gamma` in degrees, the turn from the earth frame (x east, y north, z up)
 * to the device frame (x right of the screen, y its top, z out of the screen), as
 * R = Rz(alpha) Rx(beta) Ry(gamma). The back camera looks along the device's -z, so the lens
 * axis in the earth frame is R (0, 0, -1):
 *   east  = -sin(g) cos(a) - sin(a) sin(b) cos(g)
 *   north = -sin(g) sin(a) + cos(a) sin(b) cos(g)
 *   up    = -cos(b) cos(g)
 * and the heading is atan2(east, north). The screen's turn plays no part: turning the phone
 * about its lens axis moves the picture, not the axis.
 *
 * iOS is left out: its `deviceorientation` has no absolute alpha, and `webkitCompassHeading`
 * is the compass heading of the device's top (the turn about the vertical, as a compass held
 * flat reads it), not of the lens axis of a phone held upright (docs/app.md).
 *
 * Like gravity (gravity.ts), the reading is averaged over the STILL_WINDOW_MS before the
 * shutter (a circular mean) and trusted only while the phone is still. Unlike motion events,
 * orientation events come only when an angle changes (Chromium: by more than 0.1 degree), so
 * a phone held still may send one and then none: each sample holds until the next, and the
 * one before the window is its start.
 */

import { STILL_WINDOW_MS, type StillReading, type Vector3 } from "./gravity";

/** One absolute-orientation sample: `at` in ms (performance.now()), the W3C angles in degrees. */
export interface OrientationSample {
  at: number;
  alpha: number;
  beta: number;
  gamma: number;
}

/**
 * A lens aimed more steeply than this above or below the horizon says no heading: its
 * horizontal direction is a small part of it, and the sensors' error divided by that part.
 */
export const STEEPEST_DEG = 75;
/** The headings' spread (circular standard deviation, degrees) beyond which the phone turns. */
export const TURNING_SPREAD_DEG = 5;
/**
 * No heading is claimed sharper than this (degrees): a phone's compass indoors, near a hall's
 * steel, is off by about as much (the solver's and the server's default sigma).
 */
export const COMPASS_SIGMA_DEG = 15;

/** What the phone knew of the lens's heading at the shutter ("none" too for a lens aimed
 * up or down). */
export type HeadingReading = StillReading<{ heading: number }>;

const DEGREE = Math.PI / 180;

/** The lens axis in the earth frame (x east, y north, z up; unit) for W3C angles in degrees. */
export function lensAxis(alpha: number, beta: number, gamma: number): Vector3 {
  const [a, b, g] = [alpha * DEGREE, beta * DEGREE, gamma * DEGREE];
  return [
    -Math.sin(g) * Math.cos(a) - Math.sin(a) * Math.sin(b) * Math.cos(g),
    -Math.sin(g) * Math.sin(a) + Math.cos(a) * Math.sin(b) * Math.cos(g),
    -Math.cos(b) * Math.cos(g),
  ];
}

/** Degrees wrapped to [0, 360). */
export function wrapDeg(deg: number): number {
  const wrapped = ((deg % 360) + 360) % 360;
  return wrapped === 360 ? 0 : wrapped;
}

/**
 * The lens's heading (degrees clockwise from north, in [0, 360)) for W3C angles, or null when
 * the lens is aimed more steeply than STEEPEST_DEG up or down.
 */
export function lensHeading(alpha: number, beta: number, gamma: number): number | null {
  const [east, north] = lensAxis(alpha, beta, gamma);
  if (Math.hypot(east, north) < Math.cos(STEEPEST_DEG * DEGREE)) return null;
  return wrapDeg(Math.atan2(east, north) / DEGREE);
}

/**
 * The lens's heading at the shutter (time `now`, ms), from the orientation over the last
 * STILL_WINDOW_MS (the samples in it and the one that held at its start; samples in time
 * order): their circular mean, with COMPASS_SIGMA_DEG as its sigma (a still phone's samples
 * spread far less: the compass's own error is what counts). No sample yet, a turning phone,
 * or one aimed up or down in the window says nothing.
 */
export function stillHeading(samples: readonly OrientationSample[], now: number): HeadingReading {
  const before = samples.filter((s) => s.at <= now);
  let start = 0;
  before.forEach((s, i) => {
    if (now - s.at >= STILL_WINDOW_MS) start = i;
  });
  const recent = before.slice(start);
  if (recent.length === 0) return { kind: "none" };

  const headings = recent.map((s) => lensHeading(s.alpha, s.beta, s.gamma));
  if (headings.some((h) => h === null)) return { kind: "none" };
  // The mean of unit vectors: 359 and 1 average to 0, not 180.
  let east = 0;
  let north = 0;
  for (const h of headings as number[]) {
    east += Math.sin(h * DEGREE);
    north += Math.cos(h * DEGREE);
  }
  const length = Math.min(1, Math.hypot(east, north) / headings.length);
  if (!(length > 0)) return { kind: "moving" };
  // The circular standard deviation: sqrt(-2 ln R), R the mean vector's length.
  const spreadDeg = Math.sqrt(-2 * Math.log(length)) / DEGREE;
  if (spreadDeg > TURNING_SPREAD_DEG) return { kind: "moving" };
  return {
    kind: "still",
    heading: wrapDeg(Math.atan2(east, north) / DEGREE),
    sigmaDeg: COMPASS_SIGMA_DEG,
  };
}
