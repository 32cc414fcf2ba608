import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { joinerAt7 } from "../fixtures/joiner";
import { ShownAnswer } from "./shownAnswer";
import { ViewStore } from "./view";

describe("the answer on screen", () => {
  let store: ViewStore;
  let shown: ShownAnswer;

  /** A state from the server, shown as sync.ts shows one. */
  function receive(state = joinerAt7()): void {
    store.set({ state, ...shown.patchFor(state) });
  }

  beforeEach(() => {
    vi.useFakeTimers();
    store = new ViewStore({ session_id: "s", token: "t", role: "joiner" });
    shown = new ShownAnswer(store);
  });

  afterEach(() => {
    shown.stop();
    vi.useRealTimers();
  });

  it("stays a moment while the next answer is computed, then goes", () => {
    receive();
    receive(joinerAt7({ version: 8, answer: null }));
    expect(store.view.answerState?.version).toBe(7);
    vi.advanceTimersByTime(2000);
    expect(store.view.answerState?.answer).not.toBeNull();
    vi.advanceTimersByTime(1000);
    expect(store.view.answerState?.version).toBe(8);
    expect(store.view.answerState?.answer).toBeNull();
  });

  it("gives way at once to the next answer", () => {
    receive();
    receive(joinerAt7({ version: 8, answer: null }));
    receive(joinerAt7({ version: 9 }));
    expect(store.view.answerState?.version).toBe(9);
    vi.advanceTimersByTime(3000);
    expect(store.view.answerState?.version).toBe(9);
  });

  it("is not drawn on a new photo on its way to the server", () => {
    receive();
    store.set({ photo: { size: { width: 640, height: 480 }, key: "local-1", pending: true } });
    shown.showNow();
    expect(store.view.answerState?.answer).toBeNull();
    expect(store.view.state?.answer).not.toBeNull();
  });
});
