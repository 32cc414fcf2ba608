/**
 * What each phone says about the answer: where its friend is in its own photo
 * (`answer.in_photo[you]`), the sentence, the warnings, and the landmarks to re-check. The
 * geometry is the server's; this only chooses words.
 */

import { t } from "./i18n";
import { refusalText, warningText } from "./i18n/server";
import type { AnswerDrawing, Ellipse, FriendInPhoto, Quality, Role, SessionState, SolverWarning } from "./types";
import { otherRole } from "./types";

export interface Position {
  x: number;
  y: number;
  /** Where the friend is with 95 % probability, when that is known. */
  ellipse: Ellipse | null;
  quality: Quality;
  /** "marked": this phone's own mark, refined; "on_line": the point its line gave;
   * "solved": found from the other phone's mark and the landmarks. */
  how: FriendInPhoto["how"];
}

export type AnswerKind = "none" | "curve" | "position" | "elsewhere" | "refused";

export interface AnswerView {
  kind: AnswerKind;
  /** The main sentence (empty when there is nothing to say yet). */
  text: string;
  /** Where the friend is in this phone's photo, when there is a point. */
  position: Position | null;
  /** The other phone now shows where this phone's owner is (found, not only marked). */
  seen: boolean;
  /** Whether the answer tells this phone something new (where the friend is found): the
   * view then brings it into sight. */
  news: boolean;
  /** The sentences of the warnings the server said to this phone (it chose them by the photo
   * each is about, and worded them). */
  warnings: string[];
  /** Numbers (as people see them) of landmarks that look mis-tapped. */
  suspects: number[];
  /** How sure the drawn frame is, in words a person can use ("Good: ..." / "Rough: ..."). */
  sureness: string | null;
  /** The curve the friend is on (3x3 conic, row by row), when there is no point yet. */
  curve: number[][] | null;
  /** What to draw on this phone's photo, as the server computed it (AnswerLayer renders it). */
  drawing: AnswerDrawing | null;
}

// The sentences are the catalogue's (i18n/locales): "answer.curve" is the curve alone,
// "answer.level" the level of the venue (no landmark yet, both phones' gravity),
// "answer.compass" the level with the stretch both phones' compasses point to.

/** No answer yet: nothing drawn, nothing said. */
export const NOTHING: AnswerView = {
  kind: "none",
  text: "",
  position: null,
  seen: false,
  news: false,
  warnings: [],
  suspects: [],
  sureness: null,
  curve: null,
  drawing: null,
};

/** Warnings the curve's headline says in its own words. */
const SAID_BY_THE_CURVE: ReadonlySet<SolverWarning["code"]> = new Set(["on_the_curve", "on_the_level"]);

function warningsBut(warnings: readonly SolverWarning[] | undefined, said: ReadonlySet<SolverWarning["code"]>): string[] {
  return (warnings ?? []).filter((warning) => !said.has(warning.code)).map(warningText);
}

function isInside(x: number, y: number, size: { width: number; height: number } | null | undefined): boolean {
  return !size || (x >= 0 && y >= 0 && x <= size.width && y <= size.height);
}

/** The answer as the phone of `role` tells it. */
export function describeAnswer(state: SessionState, role: Role): AnswerView {
  if (state.answer_error) {
    return { ...NOTHING, kind: "refused", text: refusalText(state.answer_error) };
  }
  const answer = state.answer;
  const mine = answer?.in_photo[role];
  if (!answer || !mine) return NOTHING;
  const theirs = answer.in_photo[otherRole(role)];
  const base = {
    warnings: (mine.warnings ?? []).map(warningText),
    suspects: answer.suspects ?? [],
    curve: mine.curve ?? null,
    drawing: mine.drawing ?? null,
    // The other phone found where this phone's owner is (not only refined its own mark).
    seen: theirs?.how === "solved" && (theirs.friend != null || theirs.curve != null || theirs.level != null),
  };
  const region = mine.region ?? null;
  const news = mine.how === "solved" || region !== null;
  const [x, y] = mine.friend ?? [Number.NaN, Number.NaN];
  const position: Position | null = mine.friend
    ? { x, y, ellipse: region, quality: answer.quality, how: mine.how }
    : null;
  const person = mine.drawing?.person;
  // This phone's own mark is what it tapped, drawn as it was (no frame): no sureness to say.
  const own = mine.how === "marked";
  const sureness = position && person && !own ? surenessText(region, answer.quality, person) : null;

  if (mine.how !== "solved") {
    // This phone marked its friend (or drew a line through them): its mark, refined.
    const text =
      theirs?.how === "marked"
        ? t("answer.markedEachOther")
        : mine.how === "on_line"
          ? t("answer.onLine")
          : t("answer.wave");
    return { ...base, kind: position ? "position" : "elsewhere", position, news, text, sureness };
  }
  if (!position) {
    // The headline says what the curve is and how to pin it down: the warning that says the
    // same for API clients is not said twice.
    const curved = { ...base, warnings: warningsBut(mine.warnings, SAID_BY_THE_CURVE), kind: "curve" as const };
    if (mine.level) {
      const text = mine.drawing?.curve?.stretch?.length ? t("answer.compass") : t("answer.level");
      return { ...curved, position: null, news, text, sureness: null };
    }
    if (mine.curve) return { ...curved, position: null, news, text: t("answer.curve"), sureness: null };
    const behind = (mine.friend_h?.[2] ?? 0) < 0;
    const text = behind
      ? t("answer.behind")
      : t("answer.farSide");
    return { ...base, kind: "elsewhere", position: null, news, text, sureness: null };
  }
  let text: string;
  if (!isInside(x, y, state.photos[role])) {
    text = t("answer.outside");
  } else if (region === null) {
    text = t("answer.likely");
  } else {
    text = t("answer.frame");
  }
  return { ...base, kind: "position", position, news, text, sureness };
}

/** A region this many people across (or fewer) is said to be good, unless the fit is poor. */
export const GOOD_PEOPLE = 2;

/**
 * How sure the frame is, in people rather than pixels of someone's photo: the 95 % region's
 * long diameter in persons far across a hall (`person` px: the answer's drawing says it).
 */
export function surenessText(region: Ellipse | null, quality: Quality, person: number): string {
  if (region === null) return t("answer.roughNoRegion");
  const people = (2 * Math.max(...region.axes)) / person;
  if (people <= GOOD_PEOPLE) {
    return quality === "poor" ? t("answer.roughDisagree") : t("answer.good");
  }
  return t("answer.roughPeople", { count: Math.round(people) });
}
