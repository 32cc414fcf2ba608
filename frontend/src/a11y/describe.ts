/**
 * The words a screen reader says for what the phone draws: each mark on the photo and
 * where the answer puts the friend ("landmark 3, placed by you, upper left"; "your friend is
 * inside the frame, upper left"). The picture itself is pixels; these sentences are its text
 * alternative (the photo view's description, a11y/PhotoDescription.tsx).
 *
 * Pure functions of the marks, the answer's geometry (answer.ts: the server's) and the
 * photo's size: no geometry is computed here but which ninth of the photo a point is in, or
 * which way off it. The words are the catalogue's (`a11y.*`, frontend/src/i18n/), in the
 * language shown: a whole sentence per case, the place put in with `{{place}}`, so each
 * language orders its sentence its own way ("rechts außerhalb des Fotos", "写真の外の右側").
 * Called at render, so a switch of language re-words them.
 */

import type { AnswerView } from "../answer";
import { t, type Catalogue } from "../i18n";
import type { TapSet } from "../landmarks";
import type { Point, Size } from "../viewTransform";

/** The photo in thirds each way (rows top to bottom, columns left to right): a place a
 * person can turn to without numbers. */
const NINTHS = [
  ["upperLeft", "upperMiddle", "upperRight"],
  ["middleLeft", "centre", "middleRight"],
  ["lowerLeft", "lowerMiddle", "lowerRight"],
] as const;

/** Off the photo: by the side(s) it is beyond. */
const OFF = {
  above: { left: "aboveLeft", right: "aboveRight", none: "above" },
  below: { left: "belowLeft", right: "belowRight", none: "below" },
  none: { left: "left", right: "right", none: null },
} as const;

/** The eight directions, from "to the right" turning clockwise on the photo (y down). */
const OCTANTS = ["right", "belowRight", "below", "belowLeft", "left", "aboveLeft", "above", "aboveRight"] as const;

function third(value: number, length: number): 0 | 1 | 2 {
  const k = Math.floor((3 * value) / length);
  return k <= 0 ? 0 : k >= 2 ? 2 : 1;
}

/** Which way off the photo point `p` is (a key of `a11y.place.off`), or null on it. */
function offPhoto(p: Point, photo: Size): keyof Catalogue["a11y"]["place"]["off"] | null {
  const vertical = p.y < 0 ? "above" : p.y > photo.height ? "below" : "none";
  const horizontal = p.x < 0 ? "left" : p.x > photo.width ? "right" : "none";
  return OFF[vertical][horizontal];
}

/**
 * Where photo point `p` is, in words: a ninth of the photo ("upper left", "centre", "lower
 * right"), or which way off it ("off the photo to the right", "off the photo above, to the
 * left").
 */
export function placeIn(p: Point, photo: Size): string {
  const off = offPhoto(p, photo);
  if (off) return t(`a11y.place.off.${off}`);
  const row = NINTHS[third(p.y, photo.height)];
  return t(`a11y.place.${row[third(p.x, photo.width)]}`);
}

/** One landmark as a screen reader says it. */
export function describeLandmark(
  id: number,
  at: Point,
  photo: Size,
  { selected = false, suspect = false }: { selected?: boolean; suspect?: boolean } = {},
): string {
  const state = suspect ? (selected ? "recheckSelected" : "recheck") : selected ? "selected" : "plain";
  return t(`a11y.landmark.${state}`, { id, place: placeIn(at, photo) });
}

/** This phone's mark on its friend (a point, or a line through them). */
export function describeFriendMark(taps: TapSet, photo: Size): string | null {
  if (taps.friend) return t("a11y.friend.point", { place: placeIn(taps.friend, photo) });
  if (taps.friend_line) return t("a11y.friend.line");
  return null;
}

/** A mark's words, and what it is ("friend", "landmark 3": a key that stays as its words change). */
export interface MarkWords {
  key: string;
  words: string;
}

/** Every mark on this phone's photo, the friend's first, then the landmarks by number. */
export function describeMarks(
  taps: TapSet,
  photo: Size,
  selected: number | null,
  suspects: readonly number[],
): MarkWords[] {
  const friend = describeFriendMark(taps, photo);
  const landmarks = [...taps.landmarks]
    .sort((a, b) => a.id - b.id)
    .map((l) => ({
      key: `landmark ${l.id}`,
      words: describeLandmark(l.id, l, photo, { selected: l.id === selected, suspect: suspects.includes(l.id) }),
    }));
  return [...(friend ? [{ key: "friend", words: friend }] : []), ...landmarks];
}

/** Which way a unit vector on the photo points (y down), to the nearest of eight. */
export function directionWords([dx, dy]: readonly [number, number]): string {
  const angle = (Math.atan2(dy, dx) * 180) / Math.PI; // 0: right, 90: down
  const octant = ((Math.round(angle / 45) % 8) + 8) % 8;
  return t(`a11y.direction.${OCTANTS[octant] ?? "right"}`);
}

/**
 * Where the answer puts the friend on this phone's photo, as a screen reader says it; null
 * when there is no answer (or it was refused: its sentence, shown, says why). The answer's
 * sentence (answer.ts) says what is drawn; this says where.
 */
export function describeAnswerPlace(answer: AnswerView, photo: Size): string | null {
  const { position } = answer;
  if (answer.kind === "none" || answer.kind === "refused") return null;
  if (answer.kind === "curve") return t("a11y.answer.curve");
  if (position) {
    const place = placeIn(position, photo);
    if (position.how === "marked") return t("a11y.answer.marked", { place });
    if (offPhoto(position, photo)) return t("a11y.answer.outside", { place });
    if (position.how === "on_line") return t("a11y.answer.onLine", { place });
    return t(position.ellipse ? "a11y.answer.frame" : "a11y.answer.likely", { place });
  }
  const arrow = answer.drawing?.arrow;
  if (arrow) return t("a11y.answer.far", { direction: directionWords(arrow.direction) });
  return null;
}
