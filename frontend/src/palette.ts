/**
 * The colours of the app's marks: the same table as the server's drawings
 * (shared_solver/drawing/palette.py, LANDMARK_COLOURS_HEX), so "the orange 3" is the same spot on
 * both phones and in the answer's overlay. tests/test_palette_contract.py compares them.
 */

export const LANDMARK_COLOURS = [
  "#3cb44b", // green
  "#4d7cff", // blue
  "#ff8c1a", // orange
  "#33e0ff", // cyan
  "#f032e6", // magenta
  "#bfef45", // lime
  "#a35cff", // violet
  "#ffa3c9", // pink
  "#1fb5a3", // teal
  "#ffffff", // white
  "#d2b48c", // tan
  "#8fa8ff", // periwinkle
] as const;

/** The friend: star, ring, arrow, curve, the buddy mark and line. */
export const FRIEND_COLOUR = "#ffd400";
/** A landmark to re-check. */
export const SUSPECT_COLOUR = "#ff1f1f";
/** Under every stroke and letter, so colours read on bright photos too. */
export const OUTLINE_COLOUR = "#141414";

/** The colour of landmark number `id` (from 1; the table repeats every 12). */
export function landmarkColour(id: number): string {
  const count = LANDMARK_COLOURS.length;
  const index = (((id - 1) % count) + count) % count;
  return LANDMARK_COLOURS[index] ?? LANDMARK_COLOURS[0];
}
