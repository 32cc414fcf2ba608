/**
 * What each phone says about the answer: the sentence, the position (for the buddy's phone),
 * the warnings, and the landmarks to re-check. The geometry is the server's; this only
 * chooses words.
 */

import type { Ellipse, Quality, Role, SessionState } from "./types";

export interface Position {
  x: number;
  y: number;
  ellipse: Ellipse | null;
  quality: Quality;
}

export type AnswerKind = "none" | "curve" | "position" | "elsewhere" | "refused";

export interface AnswerView {
  kind: AnswerKind;
  /** The main sentence (empty when there is nothing to say yet). */
  text: string;
  /** The seeker's position in the buddy's photo, when there is one. */
  position: Position | null;
  warnings: string[];
  /** Numbers (as people see them) of landmarks that look mis-tapped. */
  suspects: number[];
  /** Whether there is a server overlay to show. */
  hasOverlay: boolean;
}

export const CURVE_TEXT =
  "Your friend is somewhere on the yellow curve: 1 more landmark pins it down";

const NOTHING: AnswerView = {
  kind: "none",
  text: "",
  position: null,
  warnings: [],
  suspects: [],
  hasOverlay: false,
};

/** Landmark numbers of the answer's suspects (indices into result_landmark_ids). */
export function suspectIds(state: SessionState): number[] {
  const ids = state.result_landmark_ids ?? [];
  return (state.result?.suspect_landmarks ?? [])
    .map((index) => ids[index])
    .filter((id): id is number => id !== undefined);
}

function isInside(x: number, y: number, size: { width: number; height: number } | null): boolean {
  return size === null || (x >= 0 && y >= 0 && x <= size.width && y <= size.height);
}

/** The answer as the phone of `role` tells it. */
export function describeAnswer(state: SessionState, role: Role): AnswerView {
  if (state.result_error) {
    return { ...NOTHING, kind: "refused", text: state.result_error.message };
  }
  const result = state.result;
  if (!result) return NOTHING;
  const base = {
    warnings: result.warnings,
    suspects: suspectIds(state),
    hasOverlay: state.result_version !== null,
  };
  const forBuddy = role === "buddy";
  if (result.method === "conic") {
    return {
      ...base,
      kind: "curve",
      position: null,
      text: forBuddy
        ? CURVE_TEXT
        : "Your buddy sees a curve you stand on: 1 more landmark pins you down",
    };
  }
  const e2 = result.epipole2;
  if (!e2) {
    const behind = (result.epipole2_h?.[2] ?? 0) < 0;
    const text = forBuddy
      ? behind
        ? "Your friend is behind you: turn around."
        : "Your friend is far off to the side: follow the yellow arrow."
      : "Your buddy can now see which way you are.";
    return { ...base, kind: "elsewhere", position: null, text };
  }
  const [x, y] = e2;
  const position: Position = {
    x,
    y,
    ellipse: result.uncertainty?.ellipse ?? null,
    quality: result.quality,
  };
  const inPhoto = isInside(x, y, state.photos.buddy);
  const unsure = position.ellipse === null;
  let text: string;
  if (!forBuddy) {
    text = "Your buddy can now see where you are.";
  } else if (!inPhoto) {
    text = "Your friend is outside your photo: turn towards the yellow arrow.";
  } else if (unsure) {
    text = "Your friend is most likely at the yellow star. Ask them to mark you as a point to be sure.";
  } else {
    text = "Your friend is at the yellow star, inside the yellow ring.";
  }
  return { ...base, kind: "position", position, text };
}

/** The landmark counter: how many more landmarks both phones need for a position. */
export function neededText(count: number): string {
  if (count <= 0) return "Enough landmarks \u2713";
  return count === 1 ? "1 more landmark needed" : `${count} more landmarks needed`;
}
