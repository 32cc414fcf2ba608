import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { ApiError } from "./api";
import { taps } from "./fixtures/joiner";
import { TapSaver, type SaveStatus } from "./tapSaver";
import type { SessionState, Taps } from "./types";

const STATE = { version: 1 } as SessionState;

describe("saving taps", () => {
  let sent: Taps[];
  let answers: Array<{ resolve: (s: SessionState) => void; reject: (e: unknown) => void }>;
  let statuses: SaveStatus[];
  let ended: number;
  let settled: boolean[];
  let saver: TapSaver;

  beforeEach(() => {
    vi.useFakeTimers();
    sent = [];
    answers = [];
    statuses = [];
    ended = 0;
    settled = [];
    saver = new TapSaver({
      send: (t) =>
        new Promise((resolve, reject) => {
          sent.push(t);
          answers.push({ resolve, reject });
        }),
      onSaved: () => undefined,
      onStatus: (s) => statuses.push(s.status),
      onEnded: () => ended++,
      onSettled: () => settled.push(saver.sending),
      delay: (attempt) => 1000 * 2 ** attempt,
    });
  });

  afterEach(() => vi.useRealTimers());

  async function answer(outcome: SessionState | ApiError): Promise<void> {
    const next = answers.shift();
    if (!next) throw new Error("nothing in flight");
    if (outcome instanceof ApiError) next.reject(outcome);
    else next.resolve(outcome);
    await vi.advanceTimersByTimeAsync(0);
  }

  /** The first landmark placed and sent, and the server's answer to it: `outcome`. */
  async function firstAnswered(outcome: ApiError): Promise<void> {
    saver.update(taps(1));
    await vi.advanceTimersByTimeAsync(0);
    await answer(outcome);
  }

  it("sends a placed tap at once, waiting for nothing", async () => {
    saver.update(taps(1));
    expect(sent).toEqual([taps(1)]); // sent before any timer runs
    await answer(STATE);
    expect(statuses).toEqual(["saving", "saved"]);
  });

  it("says while a PUT is on its way, and when its reply is in, saved or not", async () => {
    expect(saver.sending).toBe(false);
    saver.update(taps(1));
    await vi.advanceTimersByTimeAsync(0);
    expect(saver.sending).toBe(true);
    await answer(new ApiError(0, "network", "offline"));
    expect(settled).toEqual([false]);
    await vi.advanceTimersByTimeAsync(1000);
    expect(saver.sending).toBe(true);
    await answer(STATE);
    expect(settled).toEqual([false, false]);
    expect(saver.sending).toBe(false);
  });

  it("sends one request at a time, then the newest taps", async () => {
    saver.update(taps(1));
    await vi.advanceTimersByTimeAsync(0);
    saver.update(taps(1, 2));
    saver.update(taps(1, 2, 3));
    await vi.advanceTimersByTimeAsync(500);
    expect(sent).toHaveLength(1);
    await answer(STATE);
    expect(statuses[statuses.length - 1]).toBe("saving");
    expect(sent).toEqual([taps(1), taps(1, 2, 3)]);
    await answer(STATE);
    expect(statuses[statuses.length - 1]).toBe("saved");
  });

  it("keeps the taps and retries with backoff when the network fails", async () => {
    saver.update(taps(1, 2));
    await vi.advanceTimersByTimeAsync(0);
    await answer(new ApiError(0, "network", "offline"));
    expect(statuses[statuses.length - 1]).toBe("error");
    expect(saver.pending).toBe(true);
    await vi.advanceTimersByTimeAsync(999);
    expect(sent).toHaveLength(1);
    await vi.advanceTimersByTimeAsync(1);
    expect(sent).toHaveLength(2);
    await answer(new ApiError(502, "http_502", "bad gateway"));
    await vi.advanceTimersByTimeAsync(2000);
    expect(sent).toHaveLength(3);
    await answer(STATE);
    expect(sent.every((t) => JSON.stringify(t) === JSON.stringify(taps(1, 2)))).toBe(true);
    expect(statuses[statuses.length - 1]).toBe("saved");
    expect(saver.pending).toBe(false);
  });

  it("retries at once when the network is back", async () => {
    await firstAnswered(new ApiError(0, "network", "offline"));
    saver.retryNow();
    await vi.advanceTimersByTimeAsync(0);
    expect(sent).toHaveLength(2);
  });

  it("does not resend taps the server refused, until they change", async () => {
    await firstAnswered(new ApiError(422, "outside_photo", "Landmark #1 is outside the photo."));
    await vi.advanceTimersByTimeAsync(60_000);
    expect(sent).toHaveLength(1);
    saver.update(taps(2));
    await vi.advanceTimersByTimeAsync(0);
    expect(sent).toHaveLength(2);
  });

  it("reports the end of the session on 401", async () => {
    await firstAnswered(new ApiError(401, "unauthorized", "This token opens no session."));
    expect(ended).toBe(1);
  });

  it("sends nothing for taps the server already has", async () => {
    saver.saved(taps(1));
    saver.update(taps(1));
    await vi.advanceTimersByTimeAsync(1000);
    expect(sent).toHaveLength(0);
    expect(statuses).toEqual([]);
  });

  it("holds taps while their photo is not on the server, then sends the newest at once", async () => {
    saver.hold(true);
    saver.update(taps(1));
    saver.update(taps(1, 2));
    await vi.advanceTimersByTimeAsync(60_000);
    expect(sent).toHaveLength(0);
    expect(saver.pending).toBe(true);
    saver.retryNow(); // the network coming back does not release a held saver
    await vi.advanceTimersByTimeAsync(1000);
    expect(sent).toHaveLength(0);
    saver.hold(false);
    await vi.advanceTimersByTimeAsync(0);
    expect(sent).toEqual([taps(1, 2)]);
    await answer(STATE);
    expect(statuses.at(-1)).toBe("saved");
  });

  it("holds a retry after a failure until released", async () => {
    saver.update(taps(1));
    await vi.advanceTimersByTimeAsync(0);
    saver.hold(true);
    await answer(new ApiError(0, "network", "No connection."));
    await vi.advanceTimersByTimeAsync(60_000);
    expect(sent).toHaveLength(1);
    saver.hold(false);
    await vi.advanceTimersByTimeAsync(0);
    expect(sent).toHaveLength(2);
  });
});
