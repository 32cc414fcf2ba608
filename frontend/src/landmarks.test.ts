import { describe, expect, it } from "vitest";
import {
  NO_TAPS,
  addLandmark,
  canUndo,
  clipLine,
  deleteLandmark,
  fromServerTaps,
  landmarkIds,
  lineThrough,
  moveLandmark,
  newEditor,
  nextLandmark,
  select,
  setFriend,
  setFriendLine,
  toServerTaps,
  undo,
  type Line,
  type TapEditor,
} from "./landmarks";
import { MAX_LANDMARKS } from "./limits";

function tapAll(editor: TapEditor, count: number, theirs: number[] = []): TapEditor {
  let next = editor;
  for (let i = 0; i < count; i++) next = addLandmark(next, { x: 10 * i, y: 5 * i }, 2.5, theirs);
  return next;
}

const FLAT: Line = { a: 0, b: 1, c: 0 };

describe("the next landmark number", () => {
  it("counts up from 1 when nobody has tapped", () => {
    expect(nextLandmark([], [])).toEqual({ id: 1, find: false });
    expect(nextLandmark([1, 2], [])).toEqual({ id: 3, find: false });
  });

  it("asks to find the lowest number the other phone has and this one lacks", () => {
    expect(nextLandmark([], [1, 2, 3])).toEqual({ id: 1, find: true });
    expect(nextLandmark([1, 2], [1, 2, 3, 4])).toEqual({ id: 3, find: true });
    expect(nextLandmark([1, 3], [1, 2, 3])).toEqual({ id: 2, find: true });
  });

  it("is a new number after every used one once all of theirs are found", () => {
    expect(nextLandmark([1, 2, 3], [1, 2, 3])).toEqual({ id: 4, find: false });
    expect(nextLandmark([1, 5], [1])).toEqual({ id: 6, find: false });
    expect(nextLandmark([1], [1, 7]).id).toBe(7);
  });

  it("passes over numbers this phone skipped as not visible", () => {
    expect(nextLandmark([1], [1, 2, 3], new Set([2]))).toEqual({ id: 3, find: true });
    expect(nextLandmark([1, 3], [1, 2, 3], new Set([2]))).toEqual({ id: 4, find: false });
  });

  it("never hands out a number this phone already has", () => {
    for (const [mine, theirs] of [
      [[1, 2, 3], [2]],
      [[2], [1, 2]],
      [[998, 999], []],
    ] as const) {
      expect(mine).not.toContain(nextLandmark(mine, theirs).id);
    }
    expect(nextLandmark([998, 999], []).id).toBe(1);
  });
});

describe("tapping landmarks", () => {
  it("numbers new landmarks 1, 2, 3 and keeps photo pixels and each tap's precision", () => {
    const editor = tapAll(newEditor(), 3);
    expect(landmarkIds(editor.taps)).toEqual([1, 2, 3]);
    expect(editor.taps.landmarks[2]).toEqual({ id: 3, x: 20, y: 10, sigma: 2.5 });
  });

  it("takes the other phone's numbers first", () => {
    const editor = tapAll(newEditor(), 3, [1, 2, 5]);
    expect(landmarkIds(editor.taps)).toEqual([1, 2, 5]);
    expect(landmarkIds(addLandmark(editor, { x: 1, y: 1 }, 2, [1, 2, 5]).taps)).toEqual([1, 2, 5, 6]);
  });

  it("never holds two landmarks with the same number", () => {
    let editor = newEditor();
    const theirs = [3, 1, 4, 1, 5];
    for (let i = 0; i < 20; i++) {
      editor = addLandmark(editor, { x: i, y: i }, 2, theirs);
      if (i % 4 === 3) editor = deleteLandmark(editor, editor.taps.landmarks[0]?.id ?? 0);
      const ids = landmarkIds(editor.taps);
      expect(new Set(ids).size).toBe(ids.length);
    }
  });

  it("stops at the most landmarks a phone may tap", () => {
    const full = tapAll(newEditor(), MAX_LANDMARKS + 3);
    expect(full.taps.landmarks).toHaveLength(MAX_LANDMARKS);
  });

  it("moves a landmark, keeping its number, with the precision of its new placement", () => {
    const editor = moveLandmark(tapAll(newEditor(), 2), 1, { x: 99.94, y: 42.06 }, 0.8);
    expect(editor.taps.landmarks[0]).toEqual({ id: 1, x: 99.9, y: 42.1, sigma: 0.8 });
    expect(editor.taps.landmarks[1]?.sigma).toBe(2.5);
    expect(editor.selected).toBe(1);
  });

  it("deletes the selected landmark and forgets the selection", () => {
    let editor = select(tapAll(newEditor(), 3), 2);
    expect(editor.selected).toBe(2);
    editor = deleteLandmark(editor, 2);
    expect(landmarkIds(editor.taps)).toEqual([1, 3]);
    expect(editor.selected).toBeNull();
  });

  it("selects only landmarks that exist", () => {
    const editor = tapAll(newEditor(), 2);
    expect(select(editor, 7).selected).toBeNull();
    expect(select(select(editor, 2), null).selected).toBeNull();
  });
});

describe("undo", () => {
  it("steps back through every change, one at a time", () => {
    let editor = newEditor();
    editor = setFriend(editor, { x: 5, y: 5 }, 3);
    editor = tapAll(editor, 2);
    editor = moveLandmark(editor, 2, { x: 50, y: 50 }, 1.2);
    editor = deleteLandmark(editor, 1);
    expect(landmarkIds(editor.taps)).toEqual([2]);
    editor = undo(editor);
    expect(landmarkIds(editor.taps)).toEqual([1, 2]);
    expect(editor.taps.landmarks[1]).toEqual({ id: 2, x: 50, y: 50, sigma: 1.2 });
    editor = undo(editor);
    expect(editor.taps.landmarks[1]).toEqual({ id: 2, x: 10, y: 5, sigma: 2.5 });
    editor = undo(undo(editor));
    expect(editor.taps.landmarks).toEqual([]);
    expect(editor.taps.friend).toEqual({ x: 5, y: 5, sigma: 3 });
    editor = undo(editor);
    expect(editor.taps).toEqual(NO_TAPS);
    expect(canUndo(editor)).toBe(false);
    expect(undo(editor)).toBe(editor);
  });

  it("does not count selecting as a change", () => {
    const editor = select(tapAll(newEditor(), 2), 1);
    expect(editor.history).toHaveLength(2);
  });

  it("drops a selection that the undone state does not have", () => {
    const editor = select(tapAll(newEditor(), 2), 2);
    expect(undo(editor).selected).toBeNull();
  });
});

describe("the friend: a mark or a line", () => {
  it("a mark replaces a line and a line replaces a mark", () => {
    const line = lineThrough({ x: 0, y: 5 }, { x: 10, y: 5 }) ?? FLAT;
    let editor = setFriendLine(newEditor(), { ...line, sigma: 4 });
    editor = setFriend(editor, { x: 3, y: 4 }, 2);
    expect(editor.taps.friend_line).toBeNull();
    editor = setFriendLine(editor, { ...line, sigma: 4 });
    expect(editor.taps.friend).toBeNull();
    expect(toServerTaps(editor.taps).friend).toBeNull();
    expect(toServerTaps(editor.taps).friend_line).toEqual({ a: 0, b: 1, c: -5, sigma: 4 });
  });

  it("a mark, or a line, can be taken back", () => {
    let editor = setFriend(newEditor(), { x: 1, y: 2 }, 1.5);
    expect(toServerTaps(editor.taps).friend).toEqual({ x: 1, y: 2, sigma: 1.5 });
    editor = setFriend(editor, null);
    expect(toServerTaps(editor.taps).friend).toBeNull();
    editor = setFriend(setFriendLine(editor, { ...FLAT, sigma: 2 }), null);
    expect(toServerTaps(editor.taps)).toMatchObject({ friend: null, friend_line: null });
  });

  it("a line through two points holds both, and is normalised", () => {
    const p = { x: 100, y: 50 };
    const q = { x: 300, y: 250 };
    const line = lineThrough(p, q);
    expect(line).not.toBeNull();
    const { a, b, c } = line ?? FLAT;
    expect(Math.hypot(a, b)).toBeCloseTo(1);
    expect(a * p.x + b * p.y + c).toBeCloseTo(0);
    expect(a * q.x + b * q.y + c).toBeCloseTo(0);
    expect(lineThrough(p, p)).toBeNull();
  });

  it("a line is drawn from edge to edge of the photo", () => {
    const size = { width: 640, height: 480 };
    const diagonal = clipLine(lineThrough({ x: 0, y: 0 }, { x: 64, y: 48 }) ?? FLAT, size);
    expect(diagonal).not.toBeNull();
    const ends = (diagonal ?? []).map((p) => [Math.round(p.x), Math.round(p.y)]).sort();
    expect(ends).toEqual([
      [0, 0],
      [640, 480],
    ]);
    expect(clipLine(lineThrough({ x: -10, y: 0 }, { x: -10, y: 5 }) ?? FLAT, size)).toBeNull();
  });
});

describe("the server's tap JSON", () => {
  it("round-trips, with each tap's precision", () => {
    const taps = {
      landmarks: [
        { id: 2, x: 5, y: 6, sigma: 2 },
        { id: 1, x: 3, y: 4, sigma: 0.9 },
      ],
      friend: { x: 7, y: 8, sigma: 1.1 },
      friend_line: null,
    };
    const local = fromServerTaps(taps);
    expect(landmarkIds(local)).toEqual([1, 2]);
    expect(toServerTaps(local)).toEqual({ ...taps, landmarks: [taps.landmarks[1], taps.landmarks[0]] }); // by number
    expect(fromServerTaps(null)).toEqual(NO_TAPS);
  });

  it("says an unknown precision as unknown (the server's default then)", () => {
    const local = fromServerTaps({ landmarks: [{ id: 1, x: 3, y: 4 }], friend_line: { a: 1, b: 0, c: -3 } });
    expect(toServerTaps(local)).toEqual({
      landmarks: [{ id: 1, x: 3, y: 4, sigma: null }],
      friend: null,
      friend_line: { a: 1, b: 0, c: -3, sigma: null },
    });
  });
});
