/**
 * One phone's taps and how they change: landmarks (numbered, matched across the phones by
 * number), the buddy mark or a line through the buddy (seeker), the seeker mark (buddy),
 * the selected landmark and an undo stack of whole tap sets.
 *
 * All functions are pure: they return a new editor and never change the one given.
 */

import type { Point, Size } from "./viewTransform";
import type { Taps } from "./types";

/** The most landmarks one phone may tap (the server's BUDDY_MAX_LANDMARKS default). */
export const MAX_LANDMARKS = 64;
/** Landmark numbers run 1..999 (the server's limit). */
export const MAX_LANDMARK_ID = 999;
/** Undo remembers this many steps. */
export const UNDO_DEPTH = 100;

export interface Landmark {
  readonly id: number;
  readonly x: number;
  readonly y: number;
}

/** a*x + b*y + c = 0 in photo pixels, with a^2 + b^2 = 1. */
export type Line = readonly [number, number, number];

export interface TapSet {
  readonly landmarks: readonly Landmark[];
  /** Seeker: where the buddy is (epipole1). */
  readonly buddyMark: Point | null;
  /** Seeker, instead of the buddy mark: a line through the buddy (epipolar_line1). */
  readonly buddyLine: Line | null;
  /** Buddy, optional: where the seeker is, when both see each other (epipole2). */
  readonly seekerMark: Point | null;
}

export interface TapEditor {
  readonly taps: TapSet;
  /** Earlier tap sets, newest last. */
  readonly history: readonly TapSet[];
  readonly selected: number | null;
}

export const NO_TAPS: TapSet = { landmarks: [], buddyMark: null, buddyLine: null, seekerMark: null };

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

/** A new landmark at `at`, numbered by {@link nextLandmark}. Unchanged when full. */
export function addLandmark(
  editor: TapEditor,
  at: Point,
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
  const landmark = { id, ...round(at) };
  const sorted = [...landmarks, landmark].sort((a, b) => a.id - b.id);
  return change(editor, { ...editor.taps, landmarks: sorted }, editor.selected);
}

export function moveLandmark(editor: TapEditor, id: number, to: Point): TapEditor {
  const { landmarks } = editor.taps;
  if (!landmarks.some((l) => l.id === id)) return editor;
  const moved = landmarks.map((l) => (l.id === id ? { id, ...round(to) } : l));
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

/** The seeker marks the buddy; a line drawn before goes (one or the other). */
export function setBuddyMark(editor: TapEditor, at: Point): TapEditor {
  return change(editor, { ...editor.taps, buddyMark: round(at), buddyLine: null }, editor.selected);
}

/** The seeker draws a line through the buddy instead of marking them. */
export function setBuddyLine(editor: TapEditor, line: Line): TapEditor {
  return change(editor, { ...editor.taps, buddyLine: line, buddyMark: null }, editor.selected);
}

/** The buddy marks the seeker (or, with null, takes the mark away). */
export function setSeekerMark(editor: TapEditor, at: Point | null): TapEditor {
  const seekerMark = at === null ? null : round(at);
  return change(editor, { ...editor.taps, seekerMark }, editor.selected);
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

// --- the line through the buddy -------------------------------------------------------------

/** The line through two photo points, normalised; null when they are the same point. */
export function lineThrough(p: Point, q: Point): Line | null {
  const a = p.y - q.y;
  const b = q.x - p.x;
  const norm = Math.hypot(a, b);
  if (norm < 1e-9) return null;
  const c = -(a * p.x + b * p.y);
  return [a / norm, b / norm, c / norm];
}

/** Where a line crosses the photo (to draw it), or null when it misses the photo. */
export function clipLine(line: Line, photo: Size): readonly [Point, Point] | null {
  const [a, b, c] = line;
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
    landmarks: taps.landmarks.map(({ id, x, y }) => ({ id, x, y })),
    epipole1: taps.buddyMark ? [taps.buddyMark.x, taps.buddyMark.y] : null,
    epipolar_line1: taps.buddyLine ? [taps.buddyLine[0], taps.buddyLine[1], taps.buddyLine[2]] : null,
    epipole2: taps.seekerMark ? [taps.seekerMark.x, taps.seekerMark.y] : null,
  };
}

export function fromServerTaps(taps: Taps | null | undefined): TapSet {
  if (!taps) return NO_TAPS;
  const point = (p: readonly [number, number] | null): Point | null =>
    p ? { x: p[0], y: p[1] } : null;
  return {
    landmarks: [...taps.landmarks].sort((a, b) => a.id - b.id).map(({ id, x, y }) => ({ id, x, y })),
    buddyMark: point(taps.epipole1),
    buddyLine: taps.epipolar_line1 ? [...taps.epipolar_line1] : null,
    seekerMark: point(taps.epipole2),
  };
}

export function sameTaps(a: TapSet, b: TapSet): boolean {
  return JSON.stringify(toServerTaps(a)) === JSON.stringify(toServerTaps(b));
}

export function landmarkIds(taps: TapSet | null | undefined): number[] {
  return taps ? taps.landmarks.map((l) => l.id) : [];
}
