import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { stubLocalStorage } from "./fixtures/localStorage";

/** storage.ts afresh: a new page load. */
async function page(): Promise<typeof import("./storage")> {
  vi.resetModules();
  return import("./storage");
}

const ANCHOR = [
  [1, 0, 0],
  [0, 0, -1],
  [0, 1, 0],
];

describe("the orientation at the shutter, kept with the photo", () => {
  beforeEach(() => {
    stubLocalStorage();
  });

  afterEach(() => vi.unstubAllGlobals());

  it("is read back for its session, on the page that read it", async () => {
    const storage = await page();
    storage.saveShutterAnchor("s1", ANCHOR);
    expect(storage.loadShutterAnchor("s1")).toEqual(ANCHOR);
    expect(storage.loadShutterAnchor("s2")).toBeNull();
  });

  it("goes with a photo that has none, and after a reload", async () => {
    const storage = await page();
    storage.saveShutterAnchor("s1", ANCHOR);
    storage.saveShutterAnchor("s1", null);
    expect(storage.loadShutterAnchor("s1")).toBeNull();
    storage.saveShutterAnchor("s1", ANCHOR);
    const reloaded = await page();
    expect(reloaded.loadShutterAnchor("s1")).toBeNull();
  });
});
