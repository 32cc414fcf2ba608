/**
 * The app's names for the API's JSON, all generated from the server's own OpenAPI schema
 * (generated/openapi.ts: `make` renews it, tests/test_api_types.py fails when it is stale),
 * and the few types of the app's own. Pixels are stored-photo pixels: x right, y down.
 */

import type { components, paths } from "./generated/openapi";

type Schemas = components["schemas"];

export type CreatedSession = Schemas["CreatedSession"];
export type Joined = Schemas["Joined"];
export type SessionState = Schemas["SessionState"];
export type PhotoStored = Schemas["PhotoStored"];
export type Taps = Schemas["Taps"];
export type LandmarkTap = Schemas["Landmark"];
export type MarkTap = Schemas["Mark"];
export type FriendLineTap = Schemas["FriendLine"];
export type Answer = Schemas["Answer"];
export type FriendInPhoto = Schemas["FriendInPhoto"];
/** A warning said to this phone: its code, parameters and sentence (docs/api.md, "Warning codes"). */
export type SolverWarning = Schemas["SolverWarning"];
/** Why there is no answer: its code, reason, parameters, sentence and the photo of its reader. */
export type Refusal = Schemas["Refusal"];
export type Ellipse = Schemas["Ellipse"];
export type LandmarkBand = Schemas["LandmarkBand"];
/** What to draw of the answer on one photo, px (shared_solver/drawing/shapes.py). */
export type AnswerDrawing = Schemas["AnswerDrawing"];
export type FrameShape = Schemas["FrameShape"];
export type CurveShape = Schemas["CurveShape"];
export type ArrowShape = Schemas["ArrowShape"];
export type LandmarkSuggestion = Schemas["LandmarkSuggestion"];
/** How this phone has turned since its photo, from a live frame matched to it ("Show me"). */
export type Reanchored = Schemas["Reanchored"];
export type Quality = Answer["quality"];
/** The data of each event type of the session's stream (JSON), by type (changes.ts). */
export type EventData = Schemas["SessionEvents"];

/** Who a phone is in its search: the friend who started it, or the one who joined it. */
export type Role = SessionState["you"];
const ROLES: readonly Role[] = ["starter", "joiner"];

/**
 * What the in-app camera read of the phone at the shutter (camera/gravity.ts), sent with the
 * photo: which way is down in the stored photo's camera frame (x right, y down the photo, z
 * into the scene; `gravity` goes as the same form field three times, x, y, z) and the
 * reading's standard deviation per axis in degrees; and, where the phone has an absolute
 * orientation, the lens's compass heading (camera/heading.ts: degrees clockwise from north)
 * and its standard deviation in degrees. A heading goes only beside gravity: the solver has
 * no use for one alone.
 */
export interface SensorFields {
  gravity: readonly [number, number, number];
  gravity_sigma_deg: number;
  heading?: number;
  heading_sigma_deg?: number;
}

/** What the phone read of its photo's EXIF lens, sent with the photo (all optional). */
export type LensFields = Omit<
  paths["/api/sessions/{session_id}/photo"]["put"]["requestBody"]["content"]["multipart/form-data"],
  "photo" | keyof SensorFields
>;

/** The form fields beside the photo: its lens and, from the in-app camera, the sensors. */
export type PhotoFields = LensFields & Partial<SensorFields>;

/** What a phone keeps to come back to its session after a reload. */
export interface Credentials {
  session_id: string;
  token: string;
  role: Role;
}

export function otherRole(role: Role): Role {
  return role === "starter" ? "joiner" : "starter";
}

export function isRole(value: unknown): value is Role {
  return ROLES.includes(value as Role);
}
