/**
 * The phone's sensors, read only while the in-app camera is open: DeviceMotionEvent's
 * `accelerationIncludingGravity`, turned into down at the shutter by gravity.ts, and the
 * absolute orientation (`deviceorientationabsolute`, where the browser has it), turned into
 * the lens's compass heading by heading.ts; each kept for the last second. Nothing else is
 * read (no location).
 *
 * Why DeviceMotionEvent and not the Generic Sensor API's GravitySensor: it is the one source
 * both engines have (iOS Safari has no Generic Sensors), it needs no permissions policy, and a
 * low-pass gravity buys nothing here, since a phone that moves at the shutter is refused
 * anyway (gravity.ts).
 *
 * iOS asks the person first: DeviceMotionEvent.requestPermission() from a tap, over HTTPS.
 * The app asks once per page, in its own words before the system's (InAppCamera.tsx).
 */

import { STILL_WINDOW_MS, stillGravity, type GravityReading, type MotionSample } from "./gravity";
import { stillHeading, type HeadingReading, type OrientationSample } from "./heading";

/** Whether the phone lets the page read its motion. */
export type MotionAccess = "granted" | "denied" | "ask";

type PermissionAsker = { requestPermission?: () => Promise<PermissionState | "granted" | "denied"> };

let answered: "granted" | "denied" | null = null;

function asker(): PermissionAsker | null {
  return typeof DeviceMotionEvent === "undefined" ? null : (DeviceMotionEvent as unknown as PermissionAsker);
}

/** "ask" only where the browser asks (iOS) and the person has not answered on this page. */
export function motionAccess(): MotionAccess {
  if (answered) return answered;
  return typeof asker()?.requestPermission === "function" ? "ask" : "granted";
}

/** Ask (from a tap): the person's answer, kept for the page; "Not now" is `ask = false`. */
export async function answerMotion(ask: boolean): Promise<"granted" | "denied"> {
  const request = asker()?.requestPermission;
  if (!ask || !request) {
    answered = ask ? "granted" : "denied";
    return answered;
  }
  try {
    answered = (await request.call(DeviceMotionEvent)) === "granted" ? "granted" : "denied";
  } catch {
    answered = "denied"; // not from a tap, or not over HTTPS
  }
  return answered;
}

/** The screen's turn from portrait (degrees anticlockwise; window.orientation on old iOS). */
export function screenAngle(): number {
  const angle = screen.orientation?.angle ?? (window as { orientation?: number }).orientation;
  return typeof angle === "number" ? angle : 0;
}

/** One sensor's samples from start() to stop(): the last two still windows of `event`. */
class SampleLog<S extends { at: number }> {
  samples: S[] = [];

  constructor(
    private readonly event: string,
    /** The sample an event carries, or null (a desktop: no sensor). */
    private readonly read: (event: Event, at: number) => S | null,
  ) {}

  private readonly listener = (event: Event): void => {
    const at = performance.now();
    const sample = this.read(event, at);
    if (!sample) return;
    this.samples.push(sample);
    // Two windows kept, and the sample that held before them (orientation events come only
    // on a change: heading.ts): enough for the shutter, bounded however long the camera is open.
    while ((this.samples[1]?.at ?? at) < at - 2 * STILL_WINDOW_MS) this.samples.shift();
  };

  start(): void {
    window.addEventListener(this.event, this.listener);
  }

  stop(): void {
    window.removeEventListener(this.event, this.listener);
    this.samples = [];
  }
}

function motionSample(event: Event, at: number): MotionSample | null {
  const a = (event as DeviceMotionEvent).accelerationIncludingGravity;
  if (a?.x == null || a.y == null || a.z == null) return null;
  return { at, reading: [a.x, a.y, a.z] };
}

function orientationSample(event: Event, at: number): OrientationSample | null {
  const { alpha, beta, gamma } = event as DeviceOrientationEvent;
  if (alpha == null || beta == null || gamma == null) return null;
  return { at, alpha, beta, gamma };
}

/**
 * Records the accelerometer and the absolute orientation from start() to stop(); reading()
 * is down at this moment, heading() the lens's heading.
 */
export class MotionRecorder {
  private readonly motion = new SampleLog("devicemotion", motionSample);
  // Chromium's earth-referenced orientation; iOS has none (heading.ts says why not its compass).
  private readonly orientation = new SampleLog("deviceorientationabsolute", orientationSample);

  start(): void {
    this.motion.start();
    this.orientation.start();
  }

  stop(): void {
    this.motion.stop();
    this.orientation.stop();
  }

  reading(): GravityReading {
    return stillGravity(this.motion.samples, performance.now(), screenAngle());
  }

  heading(): HeadingReading {
    return stillHeading(this.orientation.samples, performance.now());
  }
}
