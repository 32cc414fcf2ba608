/**
 * Which way is down in the photo at the shutter, from the phone's accelerometer.
 *
 * The reading: DeviceMotionEvent's `accelerationIncludingGravity` (W3C DeviceOrientation
 * Event, "device coordinate frame"): x to the right of the screen, y up the screen, z out of
 * the screen towards the person, in m/s^2, held in the phone's natural (portrait) posture.
 * At rest it reads the ground's push against gravity: +9.81 along the axis that points up.
 *
 * The answer: the unit vector pointing DOWN in the back camera's frame of the photo as it is
 * shown upright on screen (the frame the server takes, docs/api.md): x right along the
 * photo's rows, y down its columns, z out of the lens into the scene. A phone held upright
 * and level gives (0, 1, 0); lying flat, screen up (lens down), (0, 0, 1).
 *
 * Derivation. Down in the device frame is d = -a / |a|. The screen is turned by `angle`
 * (screen.orientation.angle: the phone turned that many degrees anticlockwise from portrait,
 * its content turned back to stay upright), so the picture's right and up are, in the device
 * frame, r = (cos t, -sin t, 0) and u = (sin t, cos t, 0). The back camera looks along -z of
 * the device. Hence down in the photo: (d . r, -(d . u), -d_z), i.e.
 *   ( -a_x cos t + a_y sin t,  a_x sin t + a_y cos t,  a_z ) / |a|.
 *
 * The reading is trusted only while the phone is still: an average over the last
 * STILL_WINDOW_MS, refused when the samples spread or their size is not gravity's (a hand
 * that moves adds its own acceleration). Its sigma is the spread per axis, floored at the
 * accelerometer's own bias (about a degree).
 */

export type Vector3 = readonly [number, number, number];

/** One accelerometer sample: `at` in ms (performance.now()), `reading` in m/s^2, device frame. */
export interface MotionSample {
  at: number;
  reading: Vector3;
}

/** Standard gravity (m/s^2). */
export const GRAVITY = 9.80665;
/** The samples averaged: those of the last STILL_WINDOW_MS before the shutter. */
export const STILL_WINDOW_MS = 500;
/**
 * Fewer samples than MIN_SAMPLES in the window, or spanning less than MIN_SPAN_MS of it, say
 * nothing (a sensor that stopped: its newest sample is then over 300 ms old). Not stricter: a
 * busy page (the camera starting, a tap being handled) holds motion events back by 100-350 ms
 * (seen in WebKitGTK, tests/e2e/test_in_app_camera.py).
 */
export const MIN_SAMPLES = 5;
export const MIN_SPAN_MS = 200;
/** The samples' spread (RMS angle from their mean, degrees) beyond which the phone moves. */
export const MOVING_SPREAD_DEG = 2;
/** How far |a| may stray from gravity (m/s^2) before it says the hand accelerates. */
export const MOVING_ACCELERATION = 1.2;
/** The accelerometer's own bias (degrees): no reading is sharper than this. */
export const SIGMA_FLOOR_DEG = 1;

/**
 * What the phone knew of a sensor at the shutter: `what` with its sigma (degrees) when the
 * phone was still; when it moved (or turned) in the window, or gave nothing usable (no, too
 * few or stale samples: a desktop, a refusal, a sensor that is off), nothing is sent.
 */
export type StillReading<What> = ({ kind: "still"; sigmaDeg: number } & What) | { kind: "moving" } | { kind: "none" };

/** What the phone knew of down at the shutter. */
export type GravityReading = StillReading<{ gravity: Vector3 }>;

const DEGREE = Math.PI / 180;

function norm(v: Vector3): number {
  return Math.hypot(v[0], v[1], v[2]);
}

function scale(v: Vector3, factor: number): Vector3 {
  return [v[0] * factor, v[1] * factor, v[2] * factor];
}

/** The screen angle as 0, 90, 180 or 270 (window.orientation says -90 for 270). */
export function screenQuarter(angle: number): number {
  return ((Math.round(angle / 90) * 90) % 360 + 360) % 360;
}

/**
 * The unit down vector in the back camera's upright photo frame, from one (or an averaged)
 * accelerometer reading in the device frame and the screen's angle (degrees, see above).
 */
export function downInPhoto(reading: Vector3, screenAngle: number): Vector3 {
  const length = norm(reading);
  if (!(length > 0)) throw new RangeError("no acceleration: no down");
  const t = screenQuarter(screenAngle) * DEGREE;
  // Exact quarter turns: no 6e-17 where a zero belongs.
  const cos = Math.round(Math.cos(t));
  const sin = Math.round(Math.sin(t));
  const [ax, ay, az] = reading;
  return scale([-ax * cos + ay * sin, ax * sin + ay * cos, az], 1 / length);
}

/**
 * Down at the shutter (time `now`, ms), from the samples of the last STILL_WINDOW_MS,
 * averaged in the device frame and turned into the photo's frame for `screenAngle`.
 */
export function stillGravity(samples: readonly MotionSample[], now: number, screenAngle: number): GravityReading {
  const recent = samples.filter((s) => s.at <= now && now - s.at <= STILL_WINDOW_MS);
  const first = recent[0];
  const last = recent[recent.length - 1];
  if (!first || !last || recent.length < MIN_SAMPLES) return { kind: "none" };
  if (last.at - first.at < MIN_SPAN_MS) return { kind: "none" };

  const sizes = recent.map((s) => norm(s.reading));
  if (sizes.some((size) => Math.abs(size - GRAVITY) > MOVING_ACCELERATION)) return { kind: "moving" };

  const units = recent.map((s, i) => scale(s.reading, 1 / (sizes[i] ?? 1)));
  const sum = units.reduce<Vector3>((acc, u) => [acc[0] + u[0], acc[1] + u[1], acc[2] + u[2]], [0, 0, 0]);
  const mean = scale(sum, 1 / norm(sum));
  // The RMS angle of the samples from their mean: two axes of spread about the mean.
  const squares = units.map((u) => {
    const cos = Math.min(1, Math.max(-1, u[0] * mean[0] + u[1] * mean[1] + u[2] * mean[2]));
    return Math.acos(cos) ** 2;
  });
  const spreadDeg = Math.sqrt(squares.reduce((a, b) => a + b, 0) / squares.length) / DEGREE;
  if (spreadDeg > MOVING_SPREAD_DEG) return { kind: "moving" };

  return {
    kind: "still",
    gravity: downInPhoto(mean, screenAngle),
    sigmaDeg: Math.max(SIGMA_FLOOR_DEG, spreadDeg / Math.SQRT2),
  };
}
