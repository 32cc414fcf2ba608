/**
 * The phone's relative orientation, read only between start() and stop(): the Generic
 * Sensor API's RelativeOrientationSensor where the browser has it (Chromium: a quaternion,
 * gyroscope and accelerometer fused, no compass), else `deviceorientation` events (iOS
 * Safari; alpha is then relative to where the page started listening, not the compass).
 * Never the absolute (compass) orientation: steel in a venue bends compasses.
 *
 * A browser that sends a reading only when it changes (Chromium's does), so the newest one
 * holds until the next: the shutter's "still" test (shutter.ts) reads it so.
 */

import { screenAngle } from "../camera/motion";
import { fromEuler, fromQuaternion, type Matrix3, type Quaternion, type Reading } from "./orientation";

export interface Sample extends Reading {
  /** performance.now() of the reading, ms. */
  at: number;
}

interface SensorLike extends EventTarget {
  quaternion?: ArrayLike<number> | null;
  start(): void;
  stop(): void;
}
type SensorClass = new (options: { frequency: number; referenceFrame?: "device" | "screen" }) => SensorLike;

type OrientationAsker = { requestPermission?: () => Promise<string> };

/**
 * iOS lets the page read `deviceorientation` only once asked from a tap (over HTTPS), a
 * question of its own beside the motion one: asked here, from the tap that opens the view.
 * Elsewhere nothing is asked.
 */
export async function askOrientation(): Promise<void> {
  const asker = typeof DeviceOrientationEvent === "undefined" ? null : (DeviceOrientationEvent as unknown as OrientationAsker);
  if (typeof asker?.requestPermission !== "function") return;
  try {
    await asker.requestPermission.call(DeviceOrientationEvent);
  } catch {
    // Not from a tap, or not over HTTPS: the view says it has no reading.
  }
}

/** Readings per second asked of the sensor: a marker that follows the hand smoothly. */
const FREQUENCY = 60;

export class OrientationSource {
  private sensor: SensorLike | null = null;
  private listening = false;
  private samples: Sample[] = [];
  private readonly keepMs: number;

  /** `keepMs`: how long readings are kept (the newest always is). */
  constructor(
    private readonly onReading: (sample: Sample) => void = () => undefined,
    keepMs = 1000,
  ) {
    this.keepMs = keepMs;
  }

  /** Readings since start() (the browser tests wait on it). */
  count = 0;

  private push(device: Matrix3): void {
    const at = performance.now();
    this.count += 1;
    const sample: Sample = { device, screenAngle: screenAngle(), at };
    this.samples.push(sample);
    while (this.samples.length > 1 && (this.samples[1]?.at ?? at) < at - this.keepMs) this.samples.shift();
    this.onReading(sample);
  }

  private readonly onOrientation = (event: DeviceOrientationEvent): void => {
    if (event.alpha == null || event.beta == null || event.gamma == null) return; // no sensor
    this.push(fromEuler(event.alpha, event.beta, event.gamma));
  };

  private listen(): void {
    if (this.listening) return;
    this.listening = true;
    window.addEventListener("deviceorientation", this.onOrientation);
  }

  start(): void {
    const Sensor = (window as { RelativeOrientationSensor?: SensorClass }).RelativeOrientationSensor;
    if (!Sensor) {
      this.listen();
      return;
    }
    try {
      const sensor = new Sensor({ frequency: FREQUENCY, referenceFrame: "device" });
      sensor.addEventListener("reading", () => {
        const q = sensor.quaternion;
        if (q && q.length === 4) this.push(fromQuaternion([q[0], q[1], q[2], q[3]] as unknown as Quaternion));
      });
      // Not allowed, or no such sensor on this phone: the events may still come.
      sensor.addEventListener("error", () => {
        sensor.stop();
        if (this.sensor === sensor) this.sensor = null;
        this.listen();
      });
      this.sensor = sensor;
      sensor.start();
    } catch {
      this.listen();
    }
  }

  stop(): void {
    this.sensor?.stop();
    this.sensor = null;
    if (this.listening) window.removeEventListener("deviceorientation", this.onOrientation);
    this.listening = false;
    this.samples = [];
  }

  /** The readings kept, oldest first (the newest holds until the next). */
  readings(): readonly Sample[] {
    return this.samples;
  }

  latest(): Sample | null {
    return this.samples[this.samples.length - 1] ?? null;
  }
}
