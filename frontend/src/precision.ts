/**
 * Each tap says how precise it is: its standard deviation (sigma) in stored-photo px, which
 * the server passes to the solver for that tap (docs/app.md).
 *
 * A finger lands within about `finger_css` CSS px of where its owner meant, the loupe's
 * cross-hair within `loupe_css`; at the moment of the tap one CSS px covers `1 / scale`
 * photo px (scale: CSS px per photo px, the view's zoom). So
 * `sigma = max(min_sigma_px, spread_css / scale)`.
 */

import { TAP_PRECISION, type TapPrecision } from "./limits";

/** How the spot was aimed: a quick tap of the finger, or adjusted under the loupe (or a mouse). */
export type Aim = "finger" | "loupe";

/** The tap's sigma, stored-photo px, rounded to 0.01 px. */
export function tapSigma(scale: number, aim: Aim, precision: TapPrecision = TAP_PRECISION): number {
  const spread = aim === "loupe" ? precision.loupe_css : precision.finger_css;
  const sigma = Math.max(precision.min_sigma_px, spread / scale);
  return Math.round(sigma * 100) / 100;
}

/**
 * A line drawn through two taps: its sigma across it. Between and near the taps the line
 * is off by no more than the larger tap's sigma, which is what it is claimed to be.
 */
export function lineSigma(first: number, second: number): number {
  return Math.max(first, second);
}
