import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { stubLocalStorage } from "../fixtures/localStorage";
import { loadDraft } from "../storage";
import { TapSaver } from "../tapSaver";
import type { SessionState, Taps } from "../types";
import { TapEditing } from "./taps";
import { ViewStore } from "./view";

/** A fresh page's taps, saved as the app saves them (session.ts): each PUT kept in `sent`,
 * its reply on its way until the test gives it (`replies`). */
function editing() {
  stubLocalStorage();
  const store = new ViewStore({ session_id: "s", token: "t", role: "joiner" });
  const sent: Taps[] = [];
  const replies: Array<(state: SessionState) => void> = [];
  const saver = new TapSaver({
    send: (put) => {
      sent.push(put);
      return new Promise<SessionState>((resolve) => replies.push(resolve));
    },
    onSaved: () => undefined,
    onStatus: (save) => taps.showSaved(save),
    onEnded: () => undefined,
  });
  const taps = new TapEditing(store, saver);
  return { store, taps, sent, replies };
}

afterEach(() => {
  vi.useRealTimers();
  vi.unstubAllGlobals();
});

describe("this phone's taps", () => {
  let store: ViewStore;
  let sent: Taps[];
  let taps: TapEditing;

  beforeEach(() => {
    ({ store, taps, sent } = editing());
  });

  it("marks the friend first, then places landmarks, sending each at once", () => {
    vi.useFakeTimers();
    taps.tap({ x: 100, y: 50, sigma: 3 });
    expect(store.view.mode).toBe("landmark");
    expect(sent).toHaveLength(1); // on its way before the mark is painted
    expect(loadDraft("s")).toBeNull(); // kept on the phone once painted (afterPaint)
    expect(store.view.save.status).toBe("saving");
    vi.advanceTimersByTime(100);
    expect(loadDraft("s")?.taps?.friend).toMatchObject({ x: 100, y: 50 });
    taps.tap({ x: 20, y: 30, sigma: 2 });
    vi.advanceTimersByTime(100);
    expect(store.view.editor.taps.friend).toMatchObject({ x: 100, y: 50 });
    expect(store.view.editor.taps.landmarks.map(({ id, x, y }) => [id, x, y])).toEqual([[1, 20, 30]]);
    expect(sent).toHaveLength(1); // the landmark waits for the PUT of the friend on its way
    expect(sent[0]?.friend).toMatchObject({ x: 100, y: 50 });
    expect(store.view.save.status).toBe("saving");
  });

  it("keeps changes made before the screen could show them together, the newest", () => {
    vi.useFakeTimers();
    taps.tap({ x: 100, y: 50, sigma: 3 });
    taps.tap({ x: 20, y: 30, sigma: 2 });
    expect(loadDraft("s")).toBeNull();
    vi.advanceTimersByTime(100);
    expect(sent).toHaveLength(1); // the landmark waits for the friend's PUT on its way
    expect(sent[0]?.landmarks).toHaveLength(0);
    expect(loadDraft("s")?.taps?.landmarks).toHaveLength(1);
  });

  it("draws a line through the friend from two points apart, waiting for the second", () => {
    vi.useFakeTimers();
    taps.setMode("line");
    taps.tap({ x: 10, y: 10, sigma: 2 });
    taps.tap({ x: 11, y: 10, sigma: 2 }); // too close to tell a direction: it starts again
    expect(store.view.linePoint).toMatchObject({ x: 11, y: 10 });
    expect(sent).toEqual([]);
    taps.tap({ x: 11, y: 60, sigma: 2 });
    expect(store.view.linePoint).toBeNull();
    expect(store.view.mode).toBe("landmark");
    vi.advanceTimersByTime(100);
    const line = sent[0]?.friend_line;
    expect(line && Math.abs(line.a * 11 + line.b * 35 + line.c)).toBeLessThan(1e-9);
  });

  it("asks for the friend again when their mark is undone, unless they cannot be seen", () => {
    taps.tap({ x: 100, y: 50, sigma: 3 });
    taps.undo();
    expect(store.view.mode).toBe("friend");
    taps.tap({ x: 100, y: 50, sigma: 3 });
    taps.cannotSee();
    taps.undo();
    expect(store.view.mode).toBe("landmark");
  });

  it("keeps what the person said on the phone for a reload", () => {
    taps.cannotSee();
    taps.skip(4);
    expect(loadDraft("s")).toMatchObject({ unseen: true, skipped: [4] });
  });
});

describe("what this phone says of its taps' saving", () => {
  it("never says saved while a tap waits for the screen, and says it once they are all saved", async () => {
    vi.useFakeTimers();
    const { store, taps, replies } = editing();
    taps.tap({ x: 100, y: 50, sigma: 3 }); // the friend: its PUT goes at once
    expect(replies).toHaveLength(1);
    replies[0]?.({} as SessionState); // and answers before the screen shows the mark
    for (let hop = 0; hop < 10; hop++) await Promise.resolve(); // its reply, no frame yet
    expect(store.view.save.status).toBe("saving"); // not "saved": not kept on the phone yet
    await vi.advanceTimersByTimeAsync(100); // shown and kept
    expect(store.view.save.status).toBe("saved");
    taps.tap({ x: 40, y: 60, sigma: 2 }); // landmark 1, undone before the screen shows it
    taps.undo();
    expect(replies).toHaveLength(2); // landmark 1's PUT went; the undone taps wait for it
    expect(store.view.save.status).toBe("saving");
    replies[1]?.({} as SessionState);
    await vi.advanceTimersByTimeAsync(100);
    expect(replies).toHaveLength(3); // the newest taps, without landmark 1
    expect(store.view.save.status).toBe("saving");
    replies[2]?.({} as SessionState);
    await vi.advanceTimersByTimeAsync(0);
    expect(store.view.save.status).toBe("saved");
    expect(loadDraft("s")?.taps?.landmarks).toHaveLength(0);
  });
});
