import { describe, expect, it } from "vitest";
import {
  GRAVITY,
  MIN_SAMPLES,
  SIGMA_FLOOR_DEG,
  STILL_WINDOW_MS,
  downInPhoto,
  screenQuarter,
  stillGravity,
  type MotionSample,
  type Vector3,
} from "./gravity";

const g = GRAVITY;
const DEGREE = Math.PI / 180;

function expectVector(got: Vector3, want: Vector3): void {
  got.forEach((value, i) => expect(value).toBeCloseTo(want[i] ?? NaN, 9));
}

/** Samples every 20 ms up to `now`, over `span` ms, of `reading(k)`. */
function samples(reading: (k: number) => Vector3, now = 1000, span = STILL_WINDOW_MS): MotionSample[] {
  const out: MotionSample[] = [];
  for (let at = now - span, k = 0; at <= now; at += 20, k += 1) out.push({ at, reading: reading(k) });
  return out;
}

function angleDeg(a: Vector3, b: Vector3): number {
  const dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return Math.acos(Math.min(1, dot / (Math.hypot(...a) * Math.hypot(...b)))) / DEGREE;
}

describe("down in the photo, from one reading", () => {
  it.each<[string, Vector3, number, Vector3]>([
    ["portrait, upright and level: the photo's down is its y", [0, g, 0], 0, [0, 1, 0]],
    ["lying flat, screen up: the lens looks down, into the scene", [0, 0, g], 0, [0, 0, 1]],
    ["lying flat, screen down: the lens looks at the sky, down is behind it", [0, 0, -g], 0, [0, 0, -1]],
    ["portrait upside down (angle 180, the picture turned back upright): still its y", [0, -g, 0], 180, [0, 1, 0]],
    ["landscape, turned anticlockwise (angle 90): the phone's right side is up", [g, 0, 0], 90, [0, 1, 0]],
  ])("%s", (_, reading, angle, down) => {
    expectVector(downInPhoto(reading, angle), down);
  });

  it("landscape, turned clockwise (angle 270, window.orientation -90): its left side is up", () => {
    expectVector(downInPhoto([-g, 0, 0], 270), [0, 1, 0]);
    expectVector(downInPhoto([-g, 0, 0], -90), [0, 1, 0]);
  });

  it("portrait, aimed 30 degrees up: down leans behind the lens", () => {
    // Looking up by a: down is (0, cos a, -sin a); the screen tips back towards the sky.
    const a = 30 * DEGREE;
    expectVector(downInPhoto([0, g * Math.cos(a), -g * Math.sin(a)], 0), [0, Math.cos(a), -Math.sin(a)]);
  });

  it("portrait, turned 10 degrees clockwise in the screen's plane: down leans to the photo's right", () => {
    // The phone's top goes right; up is then up-and-left of the screen, and down in the
    // photo down-and-right (the horizon is drawn rising to the right).
    const b = 10 * DEGREE;
    const reading: Vector3 = [-g * Math.sin(b), g * Math.cos(b), 0];
    expectVector(downInPhoto(reading, 0), [Math.sin(b), Math.cos(b), 0]);
  });

  it("landscape anticlockwise, aimed 20 degrees down: down leans into the scene", () => {
    const a = 20 * DEGREE;
    // Up is the device's +x (tipped back by a) and out of the screen (+z) by sin a.
    expectVector(downInPhoto([g * Math.cos(a), 0, g * Math.sin(a)], 90), [0, Math.cos(a), Math.sin(a)]);
  });

  it("is a unit vector whatever the reading's size", () => {
    const down = downInPhoto([1, 2, 3], 0);
    expect(Math.hypot(...down)).toBeCloseTo(1, 12);
  });

  it("reads the screen's angle to the nearest quarter turn", () => {
    expect([0, 90, 180, 270, -90, 360, 89].map(screenQuarter)).toEqual([0, 90, 180, 270, 270, 0, 90]);
  });

  it("has no down without a reading", () => {
    expect(() => downInPhoto([0, 0, 0], 0)).toThrow(RangeError);
  });
});

describe("down at the shutter, from the last moments' readings", () => {
  it("averages a still phone's readings, with the accelerometer's floor as its sigma", () => {
    const reading = stillGravity(samples(() => [0, g, 0]), 1000, 0);
    expect(reading.kind).toBe("still");
    if (reading.kind !== "still") return;
    expectVector(reading.gravity, [0, 1, 0]);
    expect(reading.sigmaDeg).toBe(SIGMA_FLOOR_DEG);
  });

  it("averages a trembling hand's readings to their mean direction, its sigma from their spread", () => {
    // +-1.8 degrees about the x axis, alternately: the mean is level; the RMS spread is 1.8.
    const tilt = 1.8 * DEGREE;
    const shaking = (k: number): Vector3 => {
      const t = k % 2 === 0 ? tilt : -tilt;
      return [0, g * Math.cos(t), g * Math.sin(t)];
    };
    const reading = stillGravity(samples(shaking), 1000, 0);
    expect(reading.kind).toBe("still");
    if (reading.kind !== "still") return;
    // As many samples up as down, or one more: their mean is level to 1.8 / 21 degrees.
    expect(angleDeg(reading.gravity, [0, 1, 0])).toBeLessThan(0.09);
    expect(reading.sigmaDeg).toBeCloseTo(1.8 / Math.SQRT2, 2);
  });

  it("turns the average for the screen's angle at the shutter", () => {
    const reading = stillGravity(samples(() => [g, 0, 0]), 1000, 90);
    expect(reading.kind === "still" && reading.gravity).toEqual([0, 1, 0]);
  });

  it("uses only the window before the shutter: an earlier tilt is forgotten", () => {
    const early = samples(() => [g, 0, 0], 400, 400);
    const late = samples(() => [0, g, 0], 1000, STILL_WINDOW_MS);
    const reading = stillGravity([...early, ...late], 1000, 0);
    expect(reading.kind === "still" && reading.gravity).toEqual([0, 1, 0]);
  });

  it("refuses a phone that turns during the window", () => {
    // 0.5 degrees every 20 ms (25 degrees a second): the readings change.
    const turning = (k: number): Vector3 => {
      const t = k * 0.5 * DEGREE;
      return [g * Math.sin(t), g * Math.cos(t), 0];
    };
    expect(stillGravity(samples(turning), 1000, 0)).toEqual({ kind: "moving" });
  });

  it("refuses a phone that is being moved (its size is not gravity's)", () => {
    // The same direction throughout, but the hand pushes at 2 m/s^2 in one sample.
    const pushed = (k: number): Vector3 => [0, k === 7 ? g + 2 : g, 0];
    expect(stillGravity(samples(pushed), 1000, 0)).toEqual({ kind: "moving" });
  });

  it("says nothing with too few, too short or stale readings", () => {
    const few = samples(() => [0, g, 0]).slice(-(MIN_SAMPLES - 1));
    expect(stillGravity(few, 1000, 0)).toEqual({ kind: "none" });
    const short = samples(() => [0, g, 0], 1000, 100);
    expect(stillGravity(short, 1000, 0)).toEqual({ kind: "none" });
    // A sensor that stopped 350 ms before the shutter.
    expect(stillGravity(samples(() => [0, g, 0], 650), 1000, 0)).toEqual({ kind: "none" });
    expect(stillGravity([], 1000, 0)).toEqual({ kind: "none" });
  });
});
