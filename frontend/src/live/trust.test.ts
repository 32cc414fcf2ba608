import { describe, expect, it } from "vitest";
import { DRIFT_MS, mayHaveDrifted, StepWatch, type MotionReading } from "./trust";

const G = 9.80665;
/** A phone's motion events: 60 a second. */
const STEP_MS = 1000 / 60;

/** A seeded random number generator (mulberry32): the same "recording" every run. */
function random(seed: number): () => number {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

function gaussian(next: () => number): number {
  return Math.sqrt(-2 * Math.log(1 - next())) * Math.cos(2 * Math.PI * next());
}

type V3 = [number, number, number];

/**
 * A recording: `world(t)` gives the phone's linear acceleration in the world (x right, y up,
 * z back towards the person, m/s^2) and its turn about the vertical (radians) at t seconds;
 * the phone is held upright, its screen tilted back by `tilt` degrees. Each reading gets a
 * hand's shake (about 9 Hz, a few tenths of m/s^2) and the sensor's noise. The device frame
 * is the world turned by the heading and the tilt, as a phone reports it.
 */
function record(seconds: number, world: (t: number) => { a: V3; heading: number }, seed: number, tilt = 15, withoutGravity = true): MotionReading[] {
  const next = random(seed);
  const phases: V3 = [next() * 6.28, next() * 6.28, next() * 6.28];
  const tiltRad = (tilt * Math.PI) / 180;
  const readings: MotionReading[] = [];
  for (let at = 0; at <= seconds * 1000; at += STEP_MS) {
    const t = at / 1000;
    const { a, heading } = world(t);
    // Into the device: the heading's turn about y undone, then the tilt about x undone.
    const [c, s] = [Math.cos(heading), Math.sin(heading)];
    const turned: V3 = [c * a[0] - s * a[2], a[1], s * a[0] + c * a[2]];
    const up: V3 = [0, G, 0];
    const toDevice = (v: V3): V3 => [v[0], Math.cos(tiltRad) * v[1] - Math.sin(tiltRad) * v[2], Math.sin(tiltRad) * v[1] + Math.cos(tiltRad) * v[2]];
    const shake = (i: 0 | 1 | 2): number => 0.25 * Math.sin(2 * Math.PI * 9 * t + phases[i]) + 0.08 * gaussian(next);
    const linear = toDevice(turned).map((v, i) => v + shake(i as 0 | 1 | 2)) as V3;
    const gravity = toDevice(up);
    readings.push({
      at,
      acceleration: withoutGravity ? linear : null,
      includingGravity: [linear[0] + gravity[0], linear[1] + gravity[1], linear[2] + gravity[2]],
    });
  }
  return readings;
}

/** Walking forward at `cadence` steps a second: each step lifts the body (a sharp push up
 * at the heel's strike, 1-3 m/s^2) and sways it side to side once every two steps. */
function walk(cadence: number, strength = 1) {
  return (t: number): { a: V3; heading: number } => {
    const phase = 2 * Math.PI * cadence * t;
    const strike = ((t * cadence) % 1) - 0.1;
    const vertical = strength * (1.4 * Math.sin(phase) + 1.6 * Math.exp(-((strike / 0.06) ** 2)) - 0.25);
    return { a: [0.5 * Math.sin(phase / 2), vertical, -0.9 * Math.sin(phase + 1)], heading: 0 };
  };
}

/** Standing still: only the hand's shake (and a slow sway of the arm). */
function stand(t: number): { a: V3; heading: number } {
  return { a: [0.1 * Math.sin(2 * Math.PI * 0.3 * t), 0.05 * Math.sin(2 * Math.PI * 0.4 * t), 0], heading: 0 };
}

/** Turning on the spot by `degrees` over `seconds` (a smooth start and stop), then back,
 * the phone at arm's length (0.4 m) from the body's axis: pulled round and sideways, up to
 * 2-3 m/s^2, but not up and down. */
function turn(degrees: number, seconds: number) {
  const r = 0.4;
  const total = (degrees * Math.PI) / 180;
  return (t: number): { a: V3; heading: number } => {
    const cycle = t % (2 * seconds);
    const sign = cycle < seconds ? 1 : -1;
    const u = (cycle % seconds) / seconds;
    // heading = total (u - sin(2 pi u) / (2 pi)): rate and acceleration zero at both ends.
    const heading = sign > 0 ? total * (u - Math.sin(2 * Math.PI * u) / (2 * Math.PI)) : total * (1 - (u - Math.sin(2 * Math.PI * u) / (2 * Math.PI)));
    const rate = (sign * total * (1 - Math.cos(2 * Math.PI * u))) / seconds;
    const angular = (sign * total * 2 * Math.PI * Math.sin(2 * Math.PI * u)) / seconds ** 2;
    // In the phone's own heading: round the body (sideways, x) and towards its axis (z).
    const [c, s] = [Math.cos(heading), Math.sin(heading)];
    const tangential = angular * r;
    const centripetal = rate * rate * r;
    return { a: [c * tangential + s * centripetal, 0, -s * tangential + c * centripetal], heading };
  };
}

function watch(readings: MotionReading[]): StepWatch {
  const steps = new StepWatch();
  readings.forEach((reading) => steps.push(reading));
  return steps;
}

describe("a phone that has moved", () => {
  it("is seen walking: steps at about 2 a second", () => {
    for (const [cadence, seed] of [
      [1.6, 1],
      [2.0, 2],
      [2.4, 3],
    ] as const) {
      expect(watch(record(4, walk(cadence), seed)).moved, `${cadence} steps a second`).toBe(true);
    }
    // A gentle walk, its steps' push about 1.5 m/s^2 at most.
    expect(watch(record(4, walk(1.8, 0.6), 4)).moved).toBe(true);
  });

  it("is not walking after one or two steps (a shuffle to see better)", () => {
    expect(watch(record(1.2, walk(2), 5)).moved).toBe(false);
  });

  it("is still while held still with a hand's shake", () => {
    const steps = watch(record(20, stand, 6));
    expect(steps.moved).toBe(false);
    expect(steps.steps).toBe(0);
  });

  it("is still while turning on the spot, back and forth", () => {
    // A quarter turn in a second, a half turn in 1.5 s: 2-6 m/s^2 round the body.
    expect(watch(record(8, turn(90, 1), 7)).moved).toBe(false);
    expect(watch(record(9, turn(180, 1.5), 8)).moved).toBe(false);
    // The sideways pull is real: a shake-free quarter turn in a second peaks above 2 m/s^2.
    const peak = Math.max(...Array.from({ length: 100 }, (_, i) => Math.hypot(...turn(90, 1)(i / 100).a)));
    expect(peak).toBeGreaterThan(2);
  });

  it("is seen walking from acceleration with gravity alone (no `acceleration`)", () => {
    expect(watch(record(4, walk(2), 9, 15, false)).moved).toBe(true);
    expect(watch(record(20, stand, 10, 15, false)).moved).toBe(false);
    // Without it the sideways pull adds to the signal to second order: a quarter turn in
    // 1.5 s is no step, a frantic one in a second back and forth can be (docs/app.md).
    expect(watch(record(9, turn(90, 1.5), 11, 15, false)).moved).toBe(false);
  });

  it("stands again after a new anchor, and starts counting again after a pause", () => {
    const steps = watch(record(4, walk(2), 12));
    expect(steps.moved).toBe(true);
    steps.reset();
    expect(steps.moved).toBe(false);
    // Two steps, a second without readings (a paused page), two more: not a walk.
    const two = record(1.1, walk(2), 13);
    two.forEach((reading) => steps.push(reading));
    two.forEach((reading) => steps.push({ ...reading, at: reading.at + 2200 }));
    expect(steps.moved).toBe(false);
  });
});

describe("a view that has run long", () => {
  it("may have drifted two minutes after its anchor", () => {
    expect(mayHaveDrifted(1000, 1000 + DRIFT_MS - 1)).toBe(false);
    expect(mayHaveDrifted(1000, 1000 + DRIFT_MS)).toBe(true);
  });
});
