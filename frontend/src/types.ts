/**
 * The JSON the server speaks (backend/sessions/schemas.py, shared_solver/result.py).
 * Pixels are stored-photo pixels: x right, y down.
 */

export type Role = "seeker" | "buddy";
export type Pixel = readonly [number, number];
export type Homogeneous = readonly [number, number, number];

export interface CreatedSession {
  session_id: string;
  join_code: string;
  join_code_expires_at: string;
  join_url: string;
  token: string;
  role: "seeker";
  expires_at: string;
}

export interface Joined {
  session_id: string;
  token: string;
  role: "buddy";
  expires_at: string;
}

export interface PhotoStored {
  width: number;
  height: number;
  scale: number;
}

export interface LandmarkTap {
  id: number;
  x: number;
  y: number;
}

/** A participant's whole tap set: each PUT replaces it. */
export interface Taps {
  landmarks: LandmarkTap[];
  epipole1: Pixel | null;
  epipolar_line1: Homogeneous | null;
  epipole2: Pixel | null;
}

export interface ParticipantState {
  joined: boolean;
  online: boolean;
}

export interface Ellipse {
  center: Pixel;
  axes: readonly [number, number];
  angle_deg: number;
}

export type Method =
  | "conic"
  | "five_point_epipole"
  | "least_squares_epipole"
  | "planar"
  | "six_point_line"
  | "two_epipoles"
  | "seven_point"
  | "eight_point"
  | "pinhole_epipole"
  | "pinhole_two_epipoles"
  | "pinhole_line"
  | "pinhole_landmarks";

export type Quality = "good" | "fair" | "poor";

/** The solver's answer (the fields the app reads). */
export interface SolveResult {
  method: Method;
  /** "pinhole": solved as two phone cameras; "projective": any two cameras. */
  camera_model?: "projective" | "pinhole";
  landmark_count: number;
  epipole2: Pixel | null;
  epipole2_h: Homogeneous | null;
  epipole1: Pixel | null;
  uncertainty: { level: number; ellipse: Ellipse | null } | null;
  suspect_landmarks: number[];
  quality: Quality;
  warnings: string[];
  candidates?: unknown[];
}

export interface SessionState {
  session_id: string;
  you: Role;
  version: number;
  expires_at: string;
  join_code: string | null;
  join_url: string | null;
  /** How many times the code was renewed after wrong codes named this search. */
  join_code_renewals: number;
  participants: Record<Role, ParticipantState>;
  photos: Record<Role, PhotoStored | null>;
  taps: Record<Role, Taps | null>;
  landmarks_needed: number;
  result: SolveResult | null;
  result_version: number | null;
  result_landmark_ids: number[] | null;
  result_error: { code: string; message: string } | null;
}

/** What a phone keeps to come back to its session after a reload. */
export interface Credentials {
  session_id: string;
  token: string;
  role: Role;
}

export function otherRole(role: Role): Role {
  return role === "seeker" ? "buddy" : "seeker";
}
