/**
 * The phone's accelerometer, read only while the in-app camera is open: DeviceMotionEvent's
 * `accelerationIncludingGravity`, kept for the last second, turned into down at the shutter
 * by gravity.ts. Nothing else is read (no orientation, no location).
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

/** Records the accelerometer from start() to stop(); reading() is down at this moment. */
export class MotionRecorder {
  private samples: MotionSample[] = [];

  private readonly listener = (event: DeviceMotionEvent): void => {
    const a = event.accelerationIncludingGravity;
    if (a?.x == null || a.y == null || a.z == null) return; // a desktop: no sensor
    const at = performance.now();
    this.samples.push({ at, reading: [a.x, a.y, a.z] });
    // Two windows kept: enough for the shutter, bounded however long the camera is open.
    while ((this.samples[0]?.at ?? at) < at - 2 * STILL_WINDOW_MS) this.samples.shift();
  };

  start(): void {
    window.addEventListener("devicemotion", this.listener);
  }

  stop(): void {
    window.removeEventListener("devicemotion", this.listener);
    this.samples = [];
  }

  reading(): GravityReading {
    return stillGravity(this.samples, performance.now(), screenAngle());
  }
}
