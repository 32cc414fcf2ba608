/**
 * What this phone's owner does next, in words, from the state: "Tap 2 more landmarks",
 * "Find #3 here", "Waiting for your friend to find #3", "Your friend sees where you are.
 * Add a landmark to sharpen it", "Done". Every count is this phone's own: the state's
 * `landmarks_needed` counts landmarks tapped in both photos, so the landmarks this phone
 * already tapped and the friend has still to find are taken off what it is asked to tap.
 */

import { t } from "./i18n";
import { nextLandmark, type NextLandmark } from "./landmarks";

export interface StepInput {
  /** The landmark numbers this phone tapped. */
  mine: readonly number[];
  /** The landmark numbers the friend's phone tapped. */
  theirs: readonly number[];
  /** Numbers this phone said it cannot see. */
  skipped: ReadonlySet<number>;
  /** Landmarks both photos still need for an answer (the state's `landmarks_needed`). */
  needed: number;
  /** Whether the friend's phone has a photo yet. */
  theirPhoto: boolean;
  /** Whether this phone marked its friend (a point or a line). */
  iMarked: boolean;
  /** Whether the friend's phone marked this phone's owner. */
  theyMarked: boolean;
  /** Whether this phone was told where its friend is (a point, a region or a curve). */
  toldWhere: boolean;
  /** Whether the friend's phone was told where this phone's owner is. */
  seen: boolean;
}

export interface Step {
  /** The short instruction, the first thing read. */
  title: string;
  /** One more line: why, or what else can be done. */
  detail: string;
  /** The landmark this phone would tap next, and whether it is one to find. */
  next: NextLandmark;
  /** "tap": a new landmark; "find": one the friend tapped; "wait": for the friend; "done". */
  kind: "tap" | "find" | "wait" | "done";
  /** How many landmarks this phone is asked to tap (0 when waiting or done). */
  toTap: number;
}

/** This phone's next step. */
export function nextStep(input: StepInput): Step {
  const next = nextLandmark(input.mine, input.theirs, input.skipped);
  const theirs = new Set(input.theirs);
  const mine = new Set(input.mine);
  // Tapped here, not yet found there: each becomes common once the friend finds it.
  const awaited = input.mine.filter((id) => !theirs.has(id)).sort((a, b) => a - b);
  const toFind = input.theirs.filter((id) => !mine.has(id) && !input.skipped.has(id));
  const toTap = Math.max(0, input.needed - awaited.length);

  if (input.needed <= 0) {
    if (toFind.length > 0) {
      return { title: t("step.findHere", { id: next.id }), detail: t("step.sharpens"), next, kind: "find", toTap: 0 };
    }
    // Told where the friend is: this phone's search is done; else it helped the other find.
    const title = input.toldWhere ? t("step.done") : input.seen ? t("step.seesYou") : t("step.done");
    const detail = input.toldWhere ? t("step.waveAndAdd") : t("step.addToSharpen");
    return { title, detail, next, kind: "done", toTap: 0 };
  }
  if (!input.theirPhoto && input.mine.length === 0) {
    return {
      title: t("step.friendTakingPhoto"),
      detail: input.iMarked ? t("step.meanwhileTap", { count: input.needed }) : t("step.markIfSee"),
      next,
      kind: "wait",
      toTap: 0,
    };
  }
  if (next.find) {
    return {
      title: t("step.findHere", { id: next.id }),
      detail: toTap > 1 ? t("step.tapThisFirst", { count: toTap }) : t("step.tapSameSpot"),
      next,
      kind: "find",
      toTap,
    };
  }
  if (toTap === 0) {
    return {
      title: t("step.waitingFind", { id: awaited[0] ?? next.id }),
      detail: t("step.meanwhileAdd"),
      next,
      kind: "wait",
      toTap: 0,
    };
  }
  // Nothing tapped on either phone, and the friend marked this phone's owner: they lead.
  if (input.mine.length === 0 && input.theirs.length === 0 && input.theyMarked && !input.iMarked) {
    return {
      title: t("step.waitingTap", { id: next.id }),
      detail: t("step.orTapYourself"),
      next,
      kind: "wait",
      toTap,
    };
  }
  return {
    title: t("step.tapMore", { count: toTap }),
    detail: t("step.spotsBoth"),
    next,
    kind: "tap",
    toTap,
  };
}
