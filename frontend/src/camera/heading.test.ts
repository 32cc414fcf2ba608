import { describe, expect, it } from "vitest";
import type { Vector3 } from "./gravity";
import {
  COMPASS_SIGMA_DEG,
  lensAxis,
  lensHeading,
  STEEPEST_DEG,
  stillHeading,
  wrapDeg,
  type OrientationSample,
} from "./heading";

const DEGREE = Math.PI / 180;

type Matrix = [Vector3, Vector3, Vector3]; // rows

function cross(a: Vector3, b: Vector3): Vector3 {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}

function unit(v: Vector3): Vector3 {
  const n = Math.hypot(...v);
  return [v[0] / n, v[1] / n, v[2] / n];
}

/**
 * The device-to-earth turn of a phone whose back camera looks `headingDeg` clockwise from
 * north and `upDeg` above the horizon, turned `rollDeg` about its lens axis from upright
 * portrait (90: on its side, 180: upside down): the device's axes (x right of the screen, y
 * its top, z out of the screen) as the matrix's columns, in the earth frame (x east, y north,
 * z up). Written from the posture, independently of heading.ts's angles.
 */
function posture(headingDeg: number, upDeg: number, rollDeg: number): Matrix {
  const [h, e, r] = [headingDeg * DEGREE, upDeg * DEGREE, rollDeg * DEGREE];
  const lens: Vector3 = [Math.sin(h) * Math.cos(e), Math.cos(h) * Math.cos(e), Math.sin(e)];
  const z: Vector3 = [-lens[0], -lens[1], -lens[2]];
  // Upright portrait: the top is the sky's side of the lens axis; the right, top x out.
  const top0 = unit([-Math.sin(e) * lens[0], -Math.sin(e) * lens[1], 1 - Math.sin(e) * lens[2]]);
  const right0 = cross(top0, z);
  const y: Vector3 = [0, 1, 2].map((i) => Math.cos(r) * top0[i]! + Math.sin(r) * right0[i]!) as unknown as Vector3;
  const x = cross(y, z);
  return [0, 1, 2].map((i) => [x[i]!, y[i]!, z[i]!]) as unknown as Matrix;
}

/**
 * The W3C angles (degrees) of a device-to-earth matrix R = Rz(alpha) Rx(beta) Ry(gamma): beta
 * in [-180, 180), gamma in (-90, 90), alpha in [0, 360) (the spec's ranges; no gimbal lock in
 * the postures tested: the lens is never exactly level with the top straight up).
 */
function w3cAngles(R: Matrix): { alpha: number; beta: number; gamma: number } {
  const gamma = Math.atan(-R[2][0] / R[2][2]);
  const cosBeta = R[2][2] / Math.cos(gamma);
  const beta = Math.atan2(R[2][1], cosBeta);
  const sign = Math.sign(cosBeta);
  const alpha = Math.atan2(-R[0][1] * sign, R[1][1] * sign);
  return { alpha: wrapDeg(alpha / DEGREE), beta: beta / DEGREE, gamma: gamma / DEGREE };
}

/** The signed difference of two headings, degrees in (-180, 180]. */
function turn(a: number, b: number): number {
  const d = wrapDeg(a - b);
  return d > 180 ? d - 360 : d;
}

/** Orientation events every 20 ms for 500 ms before `now` = 1000, each at `angles(k)`. */
function samples(angles: (k: number) => { alpha: number; beta: number; gamma: number }): OrientationSample[] {
  return Array.from({ length: 25 }, (_, k) => ({ at: 520 + 20 * k, ...angles(k) }));
}

describe("the lens's heading from the absolute orientation", () => {
  it("is north for a phone upright in portrait that looks north (alpha, beta, gamma = 0, 90, 0)", () => {
    lensAxis(0, 90, 0).forEach((v, i) => expect(v).toBeCloseTo([0, 1, 0][i]!, 12));
    expect(lensHeading(0, 90, 0)).toBe(0);
    // Turned to the east about the vertical: alpha counts anticlockwise from above.
    expect(lensHeading(270, 90, 0)).toBeCloseTo(90, 9);
  });

  for (const roll of [0, 90, 180, 270, 6, -84]) {
    it(`is the lens axis's, whatever the screen's turn (${roll} degrees about the lens)`, () => {
      for (const heading of [0, 37, 131.5, 200, 359]) {
        for (const up of [-40, -3, 20, 70]) {
          const { alpha, beta, gamma } = w3cAngles(posture(heading, up, roll));
          const read = lensHeading(alpha, beta, gamma);
          expect(read).not.toBeNull();
          expect(Math.abs(turn(read ?? Number.NaN, heading))).toBeLessThan(1e-6);
          expect(lensAxis(alpha, beta, gamma)[2]).toBeCloseTo(Math.sin(up * DEGREE), 9);
        }
      }
    });
  }

  it("says none for a lens aimed at the ceiling or the floor", () => {
    for (const up of [STEEPEST_DEG + 1, 90, -(STEEPEST_DEG + 1), -89]) {
      const { alpha, beta, gamma } = w3cAngles(posture(120, up, 0));
      expect(lensHeading(alpha, beta, gamma)).toBeNull();
    }
    // Flat on a table, screen up: the lens looks straight down.
    expect(lensHeading(30, 0, 0)).toBeNull();
  });
});

describe("the heading at the shutter", () => {
  const portraitEast = w3cAngles(posture(90, 10, 0));

  it("is the still window's circular mean: 359 and 1 average to north", () => {
    const east = stillHeading(samples(() => portraitEast), 1000);
    expect(east.kind).toBe("still");
    expect(east.kind === "still" && Math.abs(turn(east.heading, 90))).toBeLessThan(1e-6);
    expect(east.kind === "still" && east.sigmaDeg).toBe(COMPASS_SIGMA_DEG);

    const around = samples((k) => w3cAngles(posture(k % 2 ? 359 : 1, 10, 90)));
    const north = stillHeading(around, 1000);
    // 13 samples at 1 and 12 at 359: 0.04 degrees east of north (a plain mean says 179).
    expect(north.kind === "still" && Math.abs(turn(north.heading, 0))).toBeLessThan(0.05);
  });

  it("says nothing of a phone turning at the shutter", () => {
    const turning = samples((k) => w3cAngles(posture(60 + 2 * k, 10, 0)));
    expect(stillHeading(turning, 1000)).toEqual({ kind: "moving" });
  });

  it("holds a sample until the next: a still phone sends one orientation event, then none", () => {
    const once: OrientationSample[] = [{ at: 100, ...portraitEast }];
    const held = stillHeading(once, 5000);
    expect(held.kind === "still" && Math.abs(turn(held.heading, 90))).toBeLessThan(1e-6);
    // The one that held at the window's start counts, and those before it do not.
    const turned = [{ at: 100, ...w3cAngles(posture(10, 10, 0)) }, { at: 200, ...portraitEast }, { at: 4800, ...portraitEast }];
    expect(stillHeading(turned, 5000).kind).toBe("still");
    expect(stillHeading([...turned, { at: 4900, ...w3cAngles(posture(110, 10, 0)) }], 5000)).toEqual({ kind: "moving" });
  });

  it("says nothing before the first sample, nor of a lens aimed at the floor in the window", () => {
    expect(stillHeading([], 1000)).toEqual({ kind: "none" });
    expect(stillHeading([{ at: 1200, ...portraitEast }], 1000)).toEqual({ kind: "none" });
    const floor = samples((k) => w3cAngles(posture(90, k < 20 ? 10 : -85, 0)));
    expect(stillHeading(floor, 1000)).toEqual({ kind: "none" });
  });
});
