import { describe, expect, it } from "vitest";
import type { TapSet } from "./landmarks";
import { localPhoto, scaleTaps } from "./upload";

const TAPS: TapSet = {
  landmarks: [{ id: 1, x: 100, y: 50, sigma: 2 }],
  friend: { x: 10, y: 20, sigma: null },
  friend_line: null,
};

describe("the phone's own copy of its photo", () => {
  it("is shown at the size it is sent, pending until the server has it", () => {
    const body = new Blob(["jpeg"], { type: "image/jpeg" });
    const shown = localPhoto({ body, size: { width: 2560, height: 1920 }, name: "photo.jpg" }, "k1");
    expect(shown).toMatchObject({ size: { width: 2560, height: 1920 }, key: "k1", pending: true });
    expect(shown?.local).toMatch(/^blob:/);
  });

  it("is not shown when its size is unknown (the original file goes as it is)", () => {
    const body = new Blob(["heic"]);
    expect(localPhoto({ body, size: null, name: "photo.heic" }, "k2")).toBeNull();
  });
});

describe("taps moved to the stored photo's size", () => {
  it("keeps taps when the sizes match", () => {
    const size = { width: 640, height: 480 };
    expect(scaleTaps(TAPS, size, size)).toBe(TAPS);
  });

  it("scales points and sigmas", () => {
    const half = scaleTaps(TAPS, { width: 640, height: 480 }, { width: 320, height: 240 });
    expect(half.landmarks[0]).toEqual({ id: 1, x: 50, y: 25, sigma: 1 });
    expect(half.friend).toEqual({ x: 5, y: 10, sigma: null });
  });

  it("keeps a line through the same points", () => {
    // x + y - 100 = 0 through (100, 0) and (0, 100), normalised.
    const r = Math.SQRT1_2;
    const taps: TapSet = { ...TAPS, friend: null, friend_line: { a: r, b: r, c: -100 * r, sigma: 2 } };
    const line = scaleTaps(taps, { width: 200, height: 200 }, { width: 100, height: 50 }).friend_line;
    expect(line).not.toBeNull();
    if (!line) return;
    expect(Math.hypot(line.a, line.b)).toBeCloseTo(1);
    for (const [x, y] of [[50, 0], [0, 25]] as const) expect(line.a * x + line.b * y + line.c).toBeCloseTo(0);
  });
});
