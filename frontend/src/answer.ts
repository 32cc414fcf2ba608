/**
 * What each phone says about the answer: where its friend is in its own photo
 * (`answer.in_photo[you]`), the sentence, the warnings, and the landmarks to re-check. The
 * geometry is the server's; this only chooses words.
 */

import type { Ellipse, FriendInPhoto, Quality, Role, SessionState } from "./types";
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
  /** Whether the overlay tells this phone something new (it is shown without asking). */
  news: boolean;
  warnings: string[];
  /** Numbers (as people see them) of landmarks that look mis-tapped. */
  suspects: number[];
  /** Whether there is a server overlay to show. */
  hasOverlay: boolean;
}

export const CURVE_TEXT =
  "Your friend is somewhere on the yellow curve: 1 more landmark pins it down";
export const WAVE_TEXT = "Stay where you are and wave.";

const NOTHING: AnswerView = {
  kind: "none",
  text: "",
  position: null,
  seen: false,
  news: false,
  warnings: [],
  suspects: [],
  hasOverlay: false,
};

function isInside(x: number, y: number, size: { width: number; height: number } | null | undefined): boolean {
  return !size || (x >= 0 && y >= 0 && x <= size.width && y <= size.height);
}

/** The answer as the phone of `role` tells it. */
export function describeAnswer(state: SessionState, role: Role): AnswerView {
  if (state.answer_error) {
    return { ...NOTHING, kind: "refused", text: state.answer_error.message ?? "" };
  }
  const answer = state.answer;
  const mine = answer?.in_photo[role];
  if (!answer || !mine) return NOTHING;
  const theirs = answer.in_photo[otherRole(role)];
  const base = {
    warnings: mine.warnings ?? [],
    suspects: answer.suspects ?? [],
    hasOverlay: state.answer_version !== null && state.answer_version !== undefined,
    // The other phone found where this phone's owner is (not only refined its own mark).
    seen: theirs?.how === "solved" && (theirs.friend != null || theirs.curve != null),
  };
  const region = mine.region ?? null;
  const news = mine.how === "solved" || region !== null;
  const [x, y] = mine.friend ?? [Number.NaN, Number.NaN];
  const position: Position | null = mine.friend
    ? { x, y, ellipse: region, quality: answer.quality, how: mine.how }
    : null;

  if (mine.how !== "solved") {
    // This phone marked its friend (or drew a line through them): its mark, refined.
    const text =
      theirs?.how === "marked"
        ? "You marked each other: your mark, refined by the landmarks."
        : mine.how === "on_line"
          ? `Your friend is most likely at the yellow ring on your line. ${WAVE_TEXT}`
          : WAVE_TEXT;
    return { ...base, kind: position ? "position" : "elsewhere", position, news, text };
  }
  if (!position) {
    if (mine.curve) return { ...base, kind: "curve", position: null, news, text: CURVE_TEXT };
    const behind = (mine.friend_h?.[2] ?? 0) < 0;
    const text = behind
      ? "Your friend is behind you: turn around."
      : "Your friend is far off to the side: follow the yellow arrow.";
    return { ...base, kind: "elsewhere", position: null, news, text };
  }
  let text: string;
  if (!isInside(x, y, state.photos[role])) {
    text = "Your friend is outside your photo: turn towards the yellow arrow.";
  } else if (region === null) {
    text = "Your friend is most likely at the yellow star. Ask them to mark you as a point to be sure.";
  } else {
    text = "Your friend is at the yellow star, inside the yellow ring.";
  }
  return { ...base, kind: "position", position, news, text };
}

/** The landmark counter: how many more landmarks both phones need for a position. */
export function neededText(count: number): string {
  if (count <= 0) return "Enough landmarks \u2713";
  return count === 1 ? "1 more landmark needed" : `${count} more landmarks needed`;
}
