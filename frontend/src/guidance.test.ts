import { describe, expect, it } from "vitest";
import { bandBox, bandOf, misfitText, misfitsOf, outlinePoints } from "./guidance";
import type { LandmarkBand, SessionState } from "./types";

const BAND: LandmarkBand = {
  id: 4,
  start: [10, 100],
  end: [600, 140],
  half_width: [6, 14],
  outline: [
    [10, 94],
    [600, 126],
    [600, 154],
    [10, 106],
  ],
  level: 0.95,
};

function withAnswer(bands: LandmarkBand[], misfits: number[]): SessionState {
  const view = { how: "solved" as const, bands, misfits };
  return {
    answer: { in_photo: { joiner: view, starter: { how: "marked" as const } } },
  } as unknown as SessionState;
}

describe("guidance", () => {
  it("finds a landmark's band in your part of the answer only", () => {
    const state = withAnswer([BAND], []);
    expect(bandOf(state, "joiner", 4)).toBe(BAND);
    expect(bandOf(state, "joiner", 5)).toBeNull();
    expect(bandOf(state, "starter", 4)).toBeNull();
    expect(bandOf({ answer: null } as unknown as SessionState, "joiner", 4)).toBeNull();
  });

  it("says which of your landmarks do not fit, in one short sentence", () => {
    expect(misfitsOf(withAnswer([], [3]), "joiner")).toEqual([3]);
    expect(misfitText([])).toBeNull();
    expect(misfitText([3])).toBe("#3 does not fit the others: check it");
    expect(misfitText([3, 6])).toBe("#3, #6 do not fit the others: check them");
  });

  it("maps the outline to the screen and boxes it in photo pixels", () => {
    const half = (p: { x: number; y: number }) => ({ x: p.x / 2, y: p.y / 2 + 1 });
    expect(outlinePoints(BAND, half)).toBe("5.0,48.0 300.0,64.0 300.0,78.0 5.0,54.0");
    expect(bandBox(BAND)).toEqual({ min: { x: 10, y: 94 }, max: { x: 600, y: 154 } });
  });
});
