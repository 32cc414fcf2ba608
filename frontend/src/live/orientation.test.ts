import { describe, expect, it } from "vitest";
import { downInPhoto } from "../camera/gravity";
import {
  anchorAt,
  anchorFromFrame,
  apply,
  cameraToDevice,
  fromEuler,
  fromQuaternion,
  IDENTITY,
  multiply,
  rotationAngleDeg,
  sinceShutter,
  transpose,
  type Matrix3,
  type Quaternion,
  type Vector3,
} from "./orientation";

const DEGREE = Math.PI / 180;

/** The quaternion of a turn by `degrees` about a unit `axis`. */
function about(axis: Vector3, degrees: number): Quaternion {
  const half = (degrees * DEGREE) / 2;
  return [axis[0] * Math.sin(half), axis[1] * Math.sin(half), axis[2] * Math.sin(half), Math.cos(half)];
}

/** q1 q2 (Hamilton product): q2's turn first. */
function times(a: Quaternion, b: Quaternion): Quaternion {
  const [ax, ay, az, aw] = a;
  const [bx, by, bz, bw] = b;
  return [
    aw * bx + ax * bw + ay * bz - az * by,
    aw * by - ax * bz + ay * bw + az * bx,
    aw * bz + ax * by - ay * bx + az * bw,
    aw * bw - ax * bx - ay * by - az * bz,
  ];
}

function close(a: Matrix3, b: Matrix3, digits = 9): void {
  a.forEach((row, i) => row.forEach((value, j) => expect(value).toBeCloseTo(b[i]?.[j] ?? Number.NaN, digits)));
}

/** The phone upright in portrait, its back camera level (beta 90), turned `alpha` about the vertical. */
function upright(alpha = 0, beta = 90, gamma = 0): { device: Matrix3; screenAngle: number } {
  return { device: fromEuler(alpha, beta, gamma), screenAngle: 0 };
}

describe("the device's orientation as a rotation", () => {
  it("reads a quaternion as the same rotation as DeviceOrientation's angles", () => {
    close(fromQuaternion(about([0, 0, 1], 30)), fromEuler(30, 0, 0));
    close(fromQuaternion(about([1, 0, 0], 70)), fromEuler(0, 70, 0));
    close(fromQuaternion(about([0, 1, 0], -25)), fromEuler(0, 0, -25));
    // Z-X'-Y'': intrinsic, so the quaternions multiply in that order.
    const q = times(times(about([0, 0, 1], 40), about([1, 0, 0], 80)), about([0, 1, 0], 15));
    close(fromQuaternion(q), fromEuler(40, 80, 15));
  });

  it("normalises a quaternion that is unit only to the sensor's precision", () => {
    const [x, y, z, w] = about([0, 0, 1], 30);
    close(fromQuaternion([2 * x, 2 * y, 2 * z, 2 * w]), fromEuler(30, 0, 0));
    expect(() => fromQuaternion([0, 0, 0, 0])).toThrow(RangeError);
  });

  it("gives rotations", () => {
    const d = fromEuler(123, -45, 33);
    close(multiply(d, transpose(d)), IDENTITY);
    expect(rotationAngleDeg(fromEuler(17, 0, 0))).toBeCloseTo(17, 9);
  });
});

describe("the back camera's frame", () => {
  it("is the device's with y and z the other way in portrait", () => {
    close(cameraToDevice(0), [
      [1, 0, 0],
      [0, -1, 0],
      [0, 0, -1],
    ]);
  });

  it("turns with the screen as the app's gravity does, at every quarter turn", () => {
    // Down in the photo from an accelerometer reading a (up in the device frame) is C^T (-a).
    const reading: Vector3 = [3.1, -4.2, 7.7];
    const n = Math.hypot(...reading);
    for (const angle of [0, 90, 180, 270, -90]) {
      const down = apply(transpose(cameraToDevice(angle)), [-reading[0] / n, -reading[1] / n, -reading[2] / n]);
      const expected = downInPhoto(reading, angle);
      down.forEach((value, i) => expect(value).toBeCloseTo(expected[i] ?? Number.NaN, 12));
    }
  });
});

describe("the rotation since the shutter", () => {
  const ahead: Vector3 = [0, 0, 1];

  it("is none while the phone has not turned", () => {
    const shutter = upright(12);
    close(sinceShutter(anchorAt(shutter), shutter), IDENTITY);
  });

  it("moves what was ahead to the left of the view when the phone turns right", () => {
    // Turning right (clockwise seen from above) is alpha decreasing.
    const r = sinceShutter(anchorAt(upright(0)), upright(-10));
    const seen = apply(r, ahead);
    expect(seen[0]).toBeCloseTo(-Math.sin(10 * DEGREE), 12);
    expect(seen[1]).toBeCloseTo(0, 12);
    expect(seen[2]).toBeCloseTo(Math.cos(10 * DEGREE), 12);
  });

  it("moves what was ahead down the view when the phone tilts up", () => {
    // The camera aims higher when the top of the phone leans back: beta grows past 90.
    const seen = apply(sinceShutter(anchorAt(upright(0, 90)), upright(0, 98)), ahead);
    expect(seen[0]).toBeCloseTo(0, 12);
    expect(seen[1]).toBeCloseTo(Math.sin(8 * DEGREE), 12);
  });

  it("keeps the scene still when only the screen turns with the phone on its side", () => {
    // The phone turned a quarter anticlockwise in the screen's plane (gamma -90 on a phone
    // standing up), the screen's content turned back: the scene ahead stays ahead, and the
    // world's up stays up in the view.
    const portrait = { device: fromEuler(0, 90, 0), screenAngle: 0 };
    const side = { device: multiply(fromEuler(0, 90, 0), fromEuler(90, 0, 0)), screenAngle: 90 };
    close(sinceShutter(anchorAt(portrait), side), IDENTITY);
  });

  it("comes back from a frame matched to the photo", () => {
    // The true anchor; the phone later at `now`; the server reports the frame's rotation.
    const anchor = anchorAt({ device: fromEuler(30, 85, -4), screenAngle: 0 });
    const now = { device: fromEuler(21, 93, 2), screenAngle: 0 };
    const frameRotation = sinceShutter(anchor, now);
    close(anchorFromFrame(now, frameRotation), anchor);
  });
});
