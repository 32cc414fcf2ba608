/**
 * The limits the phone and the server share, read from the server's own file
 * (backend/limits.json, which backend/limits.py reads too): change them there only.
 */

import limits from "../../backend/limits.json";

/** Photos are stored at most this many px on the long side: the phone sends no more. */
export const STORED_PHOTO_SIDE: number = limits.stored_photo_side;
/** The most landmarks one phone may tap. */
export const MAX_LANDMARKS: number = limits.max_landmarks;
/** Landmark numbers run 1..MAX_LANDMARK_ID. */
export const MAX_LANDMARK_ID: number = limits.max_landmark_id;
/** Digits of a join code. */
export const CODE_DIGITS: number = limits.join_code_length;
/** The event types of the session's stream. */
export const EVENTS: readonly string[] = limits.events;

/** How precise a tap is (docs/app.md, "Each tap says how precise it is"). */
export interface TapPrecision {
  /** A finger's spread, CSS px: a tap's standard deviation on the screen. */
  readonly finger_css: number;
  /** The same, for a spot placed with the loupe (or a mouse). */
  readonly loupe_css: number;
  /** Never claimed more precise than this, stored-photo px. */
  readonly min_sigma_px: number;
}

export const TAP_PRECISION: TapPrecision = limits.tap_precision;
