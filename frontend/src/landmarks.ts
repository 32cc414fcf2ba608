/**
 * One phone's taps and how they change: landmarks (numbered, matched across the phones by
 * number), the friend (a mark where they are, or a line through them, when this phone can
 * see them), the selected landmark and an undo stack of whole tap sets. Each tap keeps its
 * precision (`sigma`, stored-photo px: precision.ts), so a moved landmark has that of its
 * new placement.
 *
 * All functions are pure: they return a new editor and never change the one given.
 */

import { MAX_LANDMARK_ID, MAX_LANDMARKS } from "./limits";
import type { FriendLineTap, LandmarkTap, MarkTap, Taps } from "./types";
import type { Point, Size } from "./viewTransform";

/** Undo remembers this many steps. */
export const UNDO_DEPTH = 100;

/** A tap as the API has it, with its precision always said (null: unknown, the server's default). */
type Precise<T extends { sigma?: number | null }> = Readonly<Omit<T, "sigma"> & { sigma: number | null }>;

export type Landmark = Precise<LandmarkTap>;
/** Where the friend is in this phone's photo. */
export type FriendMark = Precise<MarkTap>;
/** "Somewhere along here": a x + b y + c = 0 through the friend, with a^2 + b^2 = 1. */
export type FriendLine = Precise<FriendLineTap>;
/** A line without its precision (to draw, or before it is placed). */
export type Line = Pick<FriendLine, "a" | "b" | "c">;

export interface TapSet {
  readonly landmarks: readonly Landmark[];
  readonly friend: FriendMark | null;
  /** Instead of the friend mark: a line through the friend. */
  readonly friend_line: FriendLine | null;
}

export interface TapEditor {
  readonly taps: TapSet;
  /** Earlier tap sets, newest last. */
  readonly history: readonly TapSet[];
  readonly selected: number | null;
}

export const NO_TAPS: TapSet = { landmarks: [], friend: null, friend_line: null };
export function newEditor(taps: TapSet = NO_TAPS): TapEditor {
  return { taps, history: [], selected: null };
}

// --- numbering ----------------------------------------------------------------------------

export interface NextLandmark {
  readonly id: number;
  /** True when the other phone already has this number: "find #id" here. */
  readonly find: boolean;
}

/**
 * The number the next landmark on this phone gets: the lowest number the other phone has
 * and this one lacks ("find #3", unless this phone skipped it as not visible), else a new
 * number after every number either phone has used.
 */
export function nextLandmark(
  mine: readonly number[],
  theirs: readonly number[],
  skipped: ReadonlySet<number> = new Set(),
): NextLandmark {
  const have = new Set(mine);
  const missing = theirs.filter((id) => !have.has(id) && !skipped.has(id));
  if (missing.length > 0) return { id: Math.min(...missing), find: true };
  const used = [...mine, ...theirs, ...skipped];
  const next = used.length > 0 ? Math.max(...used) + 1 : 1;
  if (next <= MAX_LANDMARK_ID) return { id: next, find: false };
  // Past the last number: the lowest one nobody uses.
  const taken = new Set(used);
  for (let id = 1; id <= MAX_LANDMARK_ID; id++) if (!taken.has(id)) return { id, find: false };
  return { id: next, find: false }; // unreachable with at most 64 landmarks a phone
}

// --- changes ------------------------------------------------------------------------------

function change(editor: TapEditor, taps: TapSet, selected: number | null): TapEditor {
  const history = [...editor.history, editor.taps].slice(-UNDO_DEPTH);
  return { taps, history, selected };
}

function round(p: Point): Point {
  return { x: Math.round(p.x * 10) / 10, y: Math.round(p.y * 10) / 10 };
}

/** A new landmark at `at` (tapped with precision `sigma`), numbered by {@link nextLandmark}.
 * Unchanged when full. */
export function addLandmark(
  editor: TapEditor,
  at: Point,
  sigma: number,
  theirs: readonly number[],
  skipped: ReadonlySet<number> = new Set(),
): TapEditor {
  const { landmarks } = editor.taps;
  if (landmarks.length >= MAX_LANDMARKS) return editor;
  const { id } = nextLandmark(
    landmarks.map((l) => l.id),
    theirs,
    skipped,
  );
  const landmark = { id, ...round(at), sigma };
  const sorted = [...landmarks, landmark].sort((a, b) => a.id - b.id);
  return change(editor, { ...editor.taps, landmarks: sorted }, editor.selected);
}

/** Landmark `id` placed again at `to`, with the precision of this placement. */
export function moveLandmark(editor: TapEditor, id: number, to: Point, sigma: number): TapEditor {
  const { landmarks } = editor.taps;
  if (!landmarks.some((l) => l.id === id)) return editor;
  const moved = landmarks.map((l) => (l.id === id ? { id, ...round(to), sigma } : l));
  return change(editor, { ...editor.taps, landmarks: moved }, id);
}

export function deleteLandmark(editor: TapEditor, id: number): TapEditor {
  const { landmarks } = editor.taps;
  if (!landmarks.some((l) => l.id === id)) return editor;
  const kept = landmarks.filter((l) => l.id !== id);
  return change(editor, { ...editor.taps, landmarks: kept }, null);
}

/** Select a landmark (or none). Not a change of the taps: undo skips it. */
export function select(editor: TapEditor, id: number | null): TapEditor {
  if (id !== null && !editor.taps.landmarks.some((l) => l.id === id)) return editor;
  return { ...editor, selected: id };
}

/**
 * This phone marks its friend; a line drawn before goes. With null: the friend is no longer
 * marked (neither mark nor line).
 */
export function setFriend(editor: TapEditor, at: Point | null, sigma: number | null = null): TapEditor {
  const friend = at === null ? null : { ...round(at), sigma };
  return change(editor, { ...editor.taps, friend, friend_line: null }, editor.selected);
}

/** "Somewhere along here": a line through the friend instead of a mark. */
export function setFriendLine(editor: TapEditor, line: FriendLine): TapEditor {
  return change(editor, { ...editor.taps, friend_line: line, friend: null }, editor.selected);
}

export function canUndo(editor: TapEditor): boolean {
  return editor.history.length > 0;
}

/** Back to the tap set before the last change. */
export function undo(editor: TapEditor): TapEditor {
  const previous = editor.history[editor.history.length - 1];
  if (previous === undefined) return editor;
  const selected =
    editor.selected !== null && previous.landmarks.some((l) => l.id === editor.selected)
      ? editor.selected
      : null;
  return { taps: previous, history: editor.history.slice(0, -1), selected };
}

// --- the line through the friend ------------------------------------------------------------

/** The line through two photo points, normalised; null when they are the same point. */
export function lineThrough(p: Point, q: Point): Line | null {
  const a = p.y - q.y;
  const b = q.x - p.x;
  const norm = Math.hypot(a, b);
  if (norm < 1e-9) return null;
  const c = -(a * p.x + b * p.y);
  return { a: a / norm, b: b / norm, c: c / norm };
}

/** Where a line crosses the photo (to draw it), or null when it misses the photo. */
export function clipLine(line: Line, photo: Size): readonly [Point, Point] | null {
  const { a, b, c } = line;
  const { width: w, height: h } = photo;
  const hits: Point[] = [];
  const add = (p: Point): void => {
    const inside = p.x >= -1e-6 && p.x <= w + 1e-6 && p.y >= -1e-6 && p.y <= h + 1e-6;
    if (inside && !hits.some((q) => Math.hypot(q.x - p.x, q.y - p.y) < 1e-6)) hits.push(p);
  };
  if (Math.abs(b) > 1e-12) {
    add({ x: 0, y: -c / b });
    add({ x: w, y: -(a * w + c) / b });
  }
  if (Math.abs(a) > 1e-12) {
    add({ x: -c / a, y: 0 });
    add({ x: -(b * h + c) / a, y: h });
  }
  const [first, second] = hits;
  return first && second ? [first, second] : null;
}

// --- to and from the server -----------------------------------------------------------------

export function toServerTaps(taps: TapSet): Taps {
  return {
    landmarks: taps.landmarks.map(({ id, x, y, sigma }) => ({ id, x, y, sigma })),
    friend: taps.friend ? { ...taps.friend } : null,
    friend_line: taps.friend_line ? { ...taps.friend_line } : null,
  };
}

export function fromServerTaps(taps: Taps | null | undefined): TapSet {
  if (!taps) return NO_TAPS;
  const { friend, friend_line: line } = taps;
  return {
    landmarks: [...(taps.landmarks ?? [])]
      .sort((a, b) => a.id - b.id)
      .map(({ id, x, y, sigma }) => ({ id, x, y, sigma: sigma ?? null })),
    friend: friend ? { x: friend.x, y: friend.y, sigma: friend.sigma ?? null } : null,
    friend_line: line ? { a: line.a, b: line.b, c: line.c, sigma: line.sigma ?? null } : null,
  };
}

export function landmarkIds(taps: TapSet | null | undefined): number[] {
  return taps ? taps.landmarks.map((l) => l.id) : [];
}

/** Whether this phone has marked its friend, as a point or a line. */
export function friendMarked(taps: TapSet): boolean {
  return taps.friend !== null || taps.friend_line !== null;
}
