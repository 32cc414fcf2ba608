/**
 * What "Show me" says, in the app's words (answer.ts): where the friend is in the live view,
 * which way to turn, and what to do when the view is not anchored to the photo. The sentences
 * are the catalogue's (i18n/locales, "live"); these choose among them.
 */

import { t } from "../i18n";
import type { Pointing } from "./pointer";

/** The answer is a curve alone, no point: the 4-landmark curve, or the level both phones'
 * gravity gives (a band, worded as the tap screen words it: answer.ts). */
export type CurveKind = "curve" | "level";

/** The main sentence for where the friend is (empty: the marker says nothing by itself, or
 * the curve is on the screen); `curve`: which curve the answer is when it has no point. */
export function pointingText(pointing: Pointing | null, curve: CurveKind | null): string {
  if (!pointing) return curve ? t(`live.${curve}`) : "";
  if (pointing.kind === "in-view") return t("live.frame");
  return curve ? t(`live.turnCurve_${pointing.turn}`) : t(`live.turnFriend_${pointing.turn}`);
}

/** The words on the arrow at the edge. */
export function arrowLabel(pointing: Pointing): string {
  return pointing.kind === "off-view" ? t(`live.arrow_${pointing.turn}`) : "";
}
