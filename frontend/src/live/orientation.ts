/**
 * How the phone has turned since its photo, from its orientation sensor: the rotation that
 * carries a direction in the photo's camera frame into the live camera's, for "Show me"
 * (pointer.ts draws the answer with it).
 *
 * The readings. W3C DeviceOrientation's alpha, beta, gamma (degrees; intrinsic Z-X'-Y''),
 * or the Generic Sensor API's RelativeOrientationSensor quaternion [x, y, z, w], both as D,
 * the matrix whose columns are the device's axes in the sensor's reference frame (it takes a
 * direction in the device frame into the reference frame). The device frame: x to the right
 * of the screen, y up it, z out of the screen towards the person, in the phone's natural
 * (portrait) posture. The reference frame is the sensor's own (relative: not the compass),
 * kept while the page runs; only rotations between two readings of it are used.
 *
 * The back camera's frame, as the photo is shown upright on the screen (the frame the server
 * and camera/gravity.ts use): x right along the rows, y down the columns, z out of the lens.
 * C (cameraToDevice) takes it into the device frame: with the screen turned by `angle`
 * (screen.orientation.angle, anticlockwise), the picture's right and up are, in the device
 * frame, r = (cos t, -sin t, 0) and u = (sin t, cos t, 0), and the lens looks along -z; so
 * C's columns are r, -u and (0, 0, -1). In portrait x_cam = x_dev, y_cam = -y_dev,
 * z_cam = -z_dev.
 *
 * The anchor A = D_shutter C_shutter takes the photo's camera frame into the reference
 * frame; the rotation since the shutter is R = C_now^T D_now^T A (the photo's camera frame
 * to the live one). An anchor also comes from a frame matched to the photo on the server
 * (re-anchoring: the frame's rotation R_f from the photo, read at D_f, C_f): A = D_f C_f R_f.
 */

export type Vector3 = readonly [number, number, number];
/** A 3x3 matrix, row by row. */
export type Matrix3 = readonly [Vector3, Vector3, Vector3];
/** A unit quaternion [x, y, z, w] (the Generic Sensor API's order). */
export type Quaternion = readonly [number, number, number, number];

const DEGREE = Math.PI / 180;

export const IDENTITY: Matrix3 = [
  [1, 0, 0],
  [0, 1, 0],
  [0, 0, 1],
];

export function multiply(a: Matrix3, b: Matrix3): Matrix3 {
  const row = (i: 0 | 1 | 2): Vector3 => [
    a[i][0] * b[0][0] + a[i][1] * b[1][0] + a[i][2] * b[2][0],
    a[i][0] * b[0][1] + a[i][1] * b[1][1] + a[i][2] * b[2][1],
    a[i][0] * b[0][2] + a[i][1] * b[1][2] + a[i][2] * b[2][2],
  ];
  return [row(0), row(1), row(2)];
}

export function transpose(m: Matrix3): Matrix3 {
  return [
    [m[0][0], m[1][0], m[2][0]],
    [m[0][1], m[1][1], m[2][1]],
    [m[0][2], m[1][2], m[2][2]],
  ];
}

export function apply(m: Matrix3, v: Vector3): Vector3 {
  return [
    m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
    m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
    m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
  ];
}

/** The angle of a rotation matrix (degrees): how far apart two orientations are. */
export function rotationAngleDeg(m: Matrix3): number {
  const cos = (m[0][0] + m[1][1] + m[2][2] - 1) / 2;
  return Math.acos(Math.min(1, Math.max(-1, cos))) / DEGREE;
}

/** D from DeviceOrientation's angles (degrees): Rz(alpha) Rx(beta) Ry(gamma). */
export function fromEuler(alpha: number, beta: number, gamma: number): Matrix3 {
  const [ca, sa] = [Math.cos(alpha * DEGREE), Math.sin(alpha * DEGREE)];
  const [cb, sb] = [Math.cos(beta * DEGREE), Math.sin(beta * DEGREE)];
  const [cg, sg] = [Math.cos(gamma * DEGREE), Math.sin(gamma * DEGREE)];
  const z: Matrix3 = [
    [ca, -sa, 0],
    [sa, ca, 0],
    [0, 0, 1],
  ];
  const x: Matrix3 = [
    [1, 0, 0],
    [0, cb, -sb],
    [0, sb, cb],
  ];
  const y: Matrix3 = [
    [cg, 0, sg],
    [0, 1, 0],
    [-sg, 0, cg],
  ];
  return multiply(multiply(z, x), y);
}

/** D from a quaternion (normalised here: a sensor's is unit only to its precision). */
export function fromQuaternion(q: Quaternion): Matrix3 {
  const n = Math.hypot(q[0], q[1], q[2], q[3]);
  if (!(n > 0)) throw new RangeError("no rotation in a zero quaternion");
  const [x, y, z, w] = [q[0] / n, q[1] / n, q[2] / n, q[3] / n];
  return [
    [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
  ];
}

/** The screen angle as 0, 90, 180 or 270 (window.orientation says -90 for 270). */
function quarter(angle: number): number {
  return ((Math.round(angle / 90) * 90) % 360 + 360) % 360;
}

/** C: the back camera's upright frame into the device frame, for the screen's angle. */
export function cameraToDevice(screenAngle: number): Matrix3 {
  const t = quarter(screenAngle) * DEGREE;
  // Exact quarter turns: no 6e-17 where a zero belongs.
  const cos = Math.round(Math.cos(t));
  const sin = Math.round(Math.sin(t));
  // Columns r, -u, (0, 0, -1).
  return [
    [cos, -sin, 0],
    [-sin, -cos, 0],
    [0, 0, -1],
  ];
}

/** An orientation read from the sensor: D, and the screen's angle then. */
export interface Reading {
  device: Matrix3;
  screenAngle: number;
}

/** The anchor at the shutter: A = D C (the photo's camera frame into the reference frame). */
export function anchorAt(shutter: Reading): Matrix3 {
  return multiply(shutter.device, cameraToDevice(shutter.screenAngle));
}

/**
 * The anchor from a frame matched to the photo (re-anchoring): `frameRotation` takes a
 * direction in the photo's camera frame into the frame's, read when the orientation was
 * `atFrame`. A = D_f C_f R_f.
 */
export function anchorFromFrame(atFrame: Reading, frameRotation: Matrix3): Matrix3 {
  return multiply(anchorAt(atFrame), frameRotation);
}

/** R = C_now^T D_now^T A: a direction in the photo's camera frame into the live camera's. */
export function sinceShutter(anchor: Matrix3, now: Reading): Matrix3 {
  return multiply(transpose(anchorAt(now)), anchor);
}
