import { describe, expect, it } from "vitest";
import { NO_TAPS } from "../landmarks";
import type { LandmarkBand } from "../types";
import { opensAround } from "./PhotoView";

const band: LandmarkBand = {
  id: 4,
  start: [0, 100],
  end: [600, 300],
  half_width: [10, 20],
  level: 0.95,
  outline: [],
};

describe("what a photo opens around", () => {
  it("is the friend this phone marked, else the next landmark's spot, else its band's middle", () => {
    const friend = { x: 500, y: 90, sigma: 3 };
    const guide = { id: 4, band, spot: { x: 420, y: 260 } };
    expect(opensAround({ ...NO_TAPS, friend }, guide)).toEqual({ x: 500, y: 90 });
    expect(opensAround(NO_TAPS, guide)).toEqual({ x: 420, y: 260 });
    expect(opensAround(NO_TAPS, { ...guide, spot: null })).toEqual({ x: 300, y: 200 });
    expect(opensAround(NO_TAPS, null)).toBeNull(); // the photo's middle
  });
});
