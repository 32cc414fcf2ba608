/**
 * The words a screen reader says for what the phone draws: each mark on the photo and
 * where the answer puts the friend ("landmark 3, placed by you, upper left"; "your friend is
 * inside the frame, upper left"). The picture itself is pixels; these sentences are its text
 * alternative (the photo view's description, a11y/PhotoDescription.tsx).
 *
 * Pure functions of the marks, the answer's geometry (answer.ts: the server's) and the
 * photo's size: no geometry is computed here but which ninth of the photo a point is in.
 * Every English word of the app's accessibility lives in this folder, so it moves into the
 * catalogues (frontend/src/i18n/) in one go.
 */

import type { AnswerView } from "../answer";
import type { TapSet } from "../landmarks";
import type { Point, Size } from "../viewTransform";

/** The photo in thirds each way: a place a person can turn to without numbers. */
const ROWS = ["upper", "middle", "lower"] as const;
const COLUMNS = ["left", "centre", "right"] as const;

function third(value: number, length: number): 0 | 1 | 2 {
  const k = Math.floor((3 * value) / length);
  return k <= 0 ? 0 : k >= 2 ? 2 : 1;
}

/**
 * Where photo point `p` is, in words: a ninth of the photo ("upper left", "centre", "lower
 * right"), or which way off it ("off the photo to the right", "off the photo above, to the
 * left").
 */
export function placeIn(p: Point, photo: Size): string {
  const vertical = p.y < 0 ? "above" : p.y > photo.height ? "below" : null;
  const horizontal = p.x < 0 ? "to the left" : p.x > photo.width ? "to the right" : null;
  if (vertical || horizontal) return `off the photo ${[vertical, horizontal].filter(Boolean).join(", ")}`;
  const row = ROWS[third(p.y, photo.height)];
  const column = COLUMNS[third(p.x, photo.width)];
  if (row === "middle" && column === "centre") return "centre";
  return row === "middle" ? `middle ${column}` : `${row} ${column === "centre" ? "middle" : column}`;
}

/** One landmark as a screen reader says it. */
export function describeLandmark(
  id: number,
  at: Point,
  photo: Size,
  { selected = false, suspect = false }: { selected?: boolean; suspect?: boolean } = {},
): string {
  const parts = [`landmark ${id}, placed by you`, placeIn(at, photo)];
  if (suspect) parts.push("to re-check");
  if (selected) parts.push("selected");
  return parts.join(", ");
}

/** This phone's mark on its friend (a point, or a line through them). */
export function describeFriendMark(taps: TapSet, photo: Size): string | null {
  if (taps.friend) return `your friend, marked by you, ${placeIn(taps.friend, photo)}`;
  if (taps.friend_line) return "a line through your friend, drawn by you";
  return null;
}

/** Every mark on this phone's photo, the friend's first, then the landmarks by number. */
export function describeMarks(
  taps: TapSet,
  photo: Size,
  selected: number | null,
  suspects: readonly number[],
): string[] {
  const friend = describeFriendMark(taps, photo);
  const landmarks = [...taps.landmarks]
    .sort((a, b) => a.id - b.id)
    .map((l) => describeLandmark(l.id, l, photo, { selected: l.id === selected, suspect: suspects.includes(l.id) }));
  return [...(friend ? [friend] : []), ...landmarks];
}

/** The words for a photo without marks. */
export const NO_MARKS = "no marks yet";

/** Which way a unit vector on the photo points (y down), to the nearest of eight. */
export function directionWords([dx, dy]: readonly [number, number]): string {
  const angle = (Math.atan2(dy, dx) * 180) / Math.PI; // 0: right, 90: down
  const octant = ((Math.round(angle / 45) % 8) + 8) % 8;
  return [
    "to the right",
    "below, to the right",
    "below",
    "below, to the left",
    "to the left",
    "above, to the left",
    "above",
    "above, to the right",
  ][octant] as string;
}

/**
 * Where the answer puts the friend on this phone's photo, as a screen reader says it; null
 * when there is no answer (or it was refused: its sentence, shown, says why). The answer's
 * sentence (answer.ts) says what is drawn; this says where.
 */
export function describeAnswerPlace(answer: AnswerView, photo: Size): string | null {
  const { position } = answer;
  if (answer.kind === "none" || answer.kind === "refused") return null;
  if (answer.kind === "curve") return "your friend is somewhere on the curve drawn across the photo";
  if (position) {
    const place = placeIn(position, photo);
    const outside = place.startsWith("off the photo");
    if (position.how === "marked") return `your friend is at your mark, ${place}`;
    if (outside) return `your friend is ${place}`;
    if (position.how === "on_line") return `your friend is most likely inside the frame on your line, ${place}`;
    return position.ellipse
      ? `your friend is inside the frame, ${place}`
      : `your friend is most likely inside the frame, ${place}`;
  }
  const arrow = answer.drawing?.arrow;
  if (arrow) return `your friend is far off the photo, ${directionWords(arrow.direction)}`;
  return null;
}
