import { describe, expect, it } from "vitest";
import paletteJson from "../../shared_solver/drawing/palette.json?raw";
import css from "./styles.css?raw";
import {
  FRIEND_COLOUR,
  LANDMARK_COLOURS,
  OUTLINE_COLOUR,
  SUSPECT_COLOUR,
  applyPalette,
  landmarkColour,
  paletteProperties,
} from "./palette";

// The file as written (not through the module under test): the one source.
const source = JSON.parse(paletteJson) as {
  landmarks: Array<{ hex: string }>;
  friend: string;
  suspect: string;
  outline: string;
};
const everyColour = [...source.landmarks.map((c) => c.hex), source.friend, source.suspect, source.outline];

describe("the palette", () => {
  it("is the server's palette.json: 12 landmark colours in order, friend, suspect, outline", () => {
    expect(LANDMARK_COLOURS).toHaveLength(12);
    expect([...LANDMARK_COLOURS]).toEqual(source.landmarks.map((c) => c.hex));
    expect([FRIEND_COLOUR, SUSPECT_COLOUR, OUTLINE_COLOUR]).toEqual([source.friend, source.suspect, source.outline]);
  });

  it("paints landmark k with colour (k - 1) mod 12", () => {
    expect(landmarkColour(1)).toBe(source.landmarks[0]?.hex);
    expect(landmarkColour(3)).toBe(source.landmarks[2]?.hex);
    expect(landmarkColour(12)).toBe(source.landmarks[11]?.hex);
    expect(landmarkColour(13)).toBe(landmarkColour(1));
    expect(landmarkColour(27)).toBe(landmarkColour(3));
  });
});

describe("the stylesheet's colours", () => {
  const used = new Set([...css.matchAll(/var\((--[a-z0-9-]+)\)/g)].map((m) => m[1]));
  const defined = new Set([...css.matchAll(/^\s*(--[a-z0-9-]+)\s*:/gm)].map((m) => m[1]));

  it("hold no copy of the palette", () => {
    for (const colour of everyColour) expect(css.toLowerCase()).not.toContain(colour.toLowerCase());
  });

  it("get the palette's as custom properties set on the page, which the stylesheet uses", () => {
    const set = new Map<string, string>();
    applyPalette({ setProperty: (name: string, value: string | null) => void set.set(name, value ?? "") });
    expect(Object.fromEntries(set)).toEqual(paletteProperties());
    expect(set.get("--friend")).toBe(source.friend);
    expect(set.get("--suspect")).toBe(source.suspect);
    expect(set.get("--outline")).toBe(source.outline);
    for (const name of set.keys()) {
      expect(used.has(name)).toBe(true);
      expect(defined.has(name)).toBe(false); // never overridden by a copy in the CSS
    }
  });

  it("use no custom property that is neither defined there nor set from the palette", () => {
    const fromPalette = new Set(Object.keys(paletteProperties()));
    const missing = [...used].filter((name) => name !== undefined && name !== "--c" && !defined.has(name) && !fromPalette.has(name));
    expect(missing).toEqual([]);
  });
});
