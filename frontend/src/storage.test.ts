import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { joinerAt7 } from "./fixtures/joiner";
import { stubLocalStorage } from "./fixtures/localStorage";

/** storage.ts afresh: a new page load. */
async function page(): Promise<typeof import("./storage")> {
  vi.resetModules();
  return import("./storage");
}

beforeEach(() => {
  stubLocalStorage();
});

afterEach(() => vi.unstubAllGlobals());

const ANCHOR = [
  [1, 0, 0],
  [0, 0, -1],
  [0, 1, 0],
];

describe("the orientation at the shutter, kept with the photo", () => {
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

describe("the server's last state, kept for a reload with no signal", () => {
  it("is read back after a reload, for its own session only", async () => {
    const storage = await page();
    storage.keepState("s1", joinerAt7());
    const reloaded = await page();
    expect(reloaded.loadKeptState("s1")).toEqual(joinerAt7());
    expect(reloaded.loadKeptState("s2")).toBeNull();
  });

  it("goes with the session: left, or another one entered", async () => {
    const storage = await page();
    storage.keepState("s1", joinerAt7());
    storage.forgetSession();
    expect(storage.loadKeptState("s1")).toBeNull();
    storage.keepState("s1", joinerAt7());
    storage.saveCredentials({ session_id: "s2", token: "t", role: "joiner" });
    expect(storage.loadKeptState("s1")).toBeNull();
  });
});
