/**
 * Finding the next landmark (docs/app.md, "Guided tapping"): once there is an answer, each
 * landmark the other phone tapped and this one has not comes with its band in this photo
 * (where it must be, 95 %), and maybe a suggested spot; a landmark this phone tapped far
 * outside its band is flagged. The server computes all three (docs/api.md); this module
 * only reads them for the screen.
 */

import { t } from "./i18n";
import type { Point } from "./viewTransform";
import type { FriendInPhoto, LandmarkBand, Role, SessionState } from "./types";

/**
 * The precision of a suggested spot taken with one tap, px per axis: spots are shown only
 * when the match is sure, and those right are a median 4.8 px from the landmark
 * (docs/suggestions.md, section 3).
 */
export const SUGGESTED_SIGMA_PX = 4;

/** What this phone's part of the answer says about landmarks, or nothing before one. */
function mine(state: SessionState, you: Role): FriendInPhoto | null {
  return state.answer?.in_photo[you] ?? null;
}

/** The band of landmark `id` in your photo, when the answer gives one. */
export function bandOf(state: SessionState, you: Role, id: number): LandmarkBand | null {
  return mine(state, you)?.bands?.find((band) => band.id === id) ?? null;
}

/** Your landmarks that do not fit the others (tapped far outside their band). */
export function misfitsOf(state: SessionState, you: Role): readonly number[] {
  return mine(state, you)?.misfits ?? [];
}

/** The flag for the compact status: short, naming the landmarks. */
export function misfitText(misfits: readonly number[]): string | null {
  if (misfits.length === 0) return null;
  const names = misfits.map((id) => `#${id}`).join(", ");
  return t("answer.misfit", { count: misfits.length, names });
}

/** The band's outline on the screen, as an SVG `points` attribute. */
export function outlinePoints(band: LandmarkBand, toScreen: (p: Point) => Point): string {
  return band.outline
    .map(([x, y]) => toScreen({ x, y }))
    .map((p) => `${p.x.toFixed(1)},${p.y.toFixed(1)}`)
    .join(" ");
}

/** The band's bounding box in photo pixels: what a reframe shows to find the landmark. */
export function bandBox(band: LandmarkBand): { min: Point; max: Point } {
  const xs = band.outline.map((p) => p[0]);
  const ys = band.outline.map((p) => p[1]);
  return { min: { x: Math.min(...xs), y: Math.min(...ys) }, max: { x: Math.max(...xs), y: Math.max(...ys) } };
}
