import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { ApiError, isRetryable } from "./api";
import type { Change } from "./changes";
import { FakeSource } from "./fixtures/eventSource";
import { LiveStream, Refetcher, backoffDelay, withRetry, type StreamStatus } from "./reconnect";

describe("backoff", () => {
  const exact = { jitter: 0 };

  it("doubles from the base delay up to the cap", () => {
    expect([0, 1, 2, 3].map((n) => backoffDelay(n, { ...exact, baseMs: 500 }))).toEqual([
      500, 1000, 2000, 4000,
    ]);
    expect(backoffDelay(20, { ...exact, baseMs: 1000, maxMs: 30_000 })).toBe(30_000);
  });

  it("spreads retries by the jitter, never past the cap", () => {
    expect(backoffDelay(1, { baseMs: 1000, jitter: 0.2, random: () => 0 })).toBe(1600);
    expect(backoffDelay(1, { baseMs: 1000, jitter: 0.2, random: () => 1 })).toBe(2400);
    expect(backoffDelay(9, { baseMs: 1000, maxMs: 5000, jitter: 0.2, random: () => 1 })).toBe(5000);
  });
});

describe("retrying", () => {
  const noWait = { delay: () => 0, sleep: async () => undefined };

  it("tries again after network errors, and succeeds", async () => {
    let calls = 0;
    const result = await withRetry(
      async () => {
        calls++;
        if (calls < 3) throw new ApiError(0, "network", "offline");
        return "stored";
      },
      { retries: 3, isRetryable, ...noWait },
    );
    expect(result).toBe("stored");
    expect(calls).toBe(3);
  });

  it.each([
    ["gives up after the last retry", new ApiError(0, "network", "offline"), 2, 3],
    [
      "does not retry a refusal (the same photo would be refused again)",
      new ApiError(415, "unsupported_photo", "HEIC could not be converted."),
      5,
      1,
    ],
  ] as const)("%s", async (_, error, retries, tries) => {
    let calls = 0;
    const failing = withRetry(
      async () => {
        calls++;
        throw error;
      },
      { retries, isRetryable, ...noWait },
    );
    await expect(failing).rejects.toThrow(error.message);
    expect(calls).toBe(tries);
  });

  it("waits the backoff between tries", async () => {
    const waits: number[] = [];
    await withRetry(
      async (attempt) => {
        if (attempt < 2) throw new ApiError(503, "busy", "busy");
        return 1;
      },
      {
        retries: 4,
        isRetryable,
        delay: (n) => backoffDelay(n, { baseMs: 100, jitter: 0 }),
        sleep: async (ms) => {
          waits.push(ms);
        },
      },
    );
    expect(waits).toEqual([100, 200]);
  });
});

describe("fetching the state", () => {
  it("runs one fetch at a time and one more for any asks meanwhile", async () => {
    const finishers: Array<() => void> = [];
    let started = 0;
    const refetcher = new Refetcher(
      () =>
        new Promise<void>((done) => {
          started++;
          finishers.push(done);
        }),
    );
    refetcher.request();
    refetcher.request();
    refetcher.request();
    expect(started).toBe(1);
    finishers.shift()?.();
    await Promise.resolve();
    await Promise.resolve();
    expect(started).toBe(2);
    finishers.shift()?.();
    await Promise.resolve();
    await Promise.resolve();
    expect(started).toBe(2);
    refetcher.request();
    expect(started).toBe(3);
  });
});

describe("the event stream", () => {
  /** What each change told, in order: as many as there were changes. */
  let told: Array<Change | undefined>;
  let ended: number;
  let statuses: StreamStatus[];

  beforeEach(() => {
    vi.useFakeTimers();
    FakeSource.opened = [];
    told = [];
    ended = 0;
    statuses = [];
  });

  afterEach(() => {
    vi.useRealTimers();
  });

  function stream(): LiveStream {
    const live = new LiveStream({
      url: "/events",
      onChange: (change) => told.push(change),
      onEnded: () => ended++,
      onStatus: (status) => statuses.push(status),
      open: (url) => new FakeSource(url),
      delay: (attempt) => 1000 * 2 ** attempt,
    });
    live.start();
    return live;
  }

  function latest(): FakeSource {
    const source = FakeSource.opened[FakeSource.opened.length - 1];
    if (!source) throw new Error("no stream opened");
    return source;
  }

  it("tells of a change when it opens and on every change event", () => {
    stream();
    latest().open();
    expect(statuses).toEqual(["up"]);
    expect(told).toHaveLength(1);
    for (const type of ["joined", "code", "photo", "taps", "answer", "left"]) latest().emit(type);
    expect(told).toHaveLength(7);
  });

  it("tells what changed with the event's data", () => {
    stream();
    latest().open();
    latest().emit("taps", '{"role": "joiner", "version": 9}');
    latest().emit("answer", '{"version": 9}');
    latest().emit("joined", '{"role": "joiner", "online": true}');
    latest().emit("photo", "not json");
    expect(told).toEqual([
      undefined, // opened: anything may have changed
      { type: "taps", data: { role: "joiner", version: 9 } },
      { type: "answer", data: { version: 9 } },
      { type: "joined", data: { role: "joiner", online: true } },
      { type: "photo", data: null },
    ]);
  });

  it("shows the stream down while EventSource reconnects, and fetches when it is back", () => {
    stream();
    latest().open();
    latest().drop();
    expect(statuses).toEqual(["up", "down"]);
    expect(FakeSource.opened).toHaveLength(1); // EventSource retries by itself
    latest().open();
    expect(statuses).toEqual(["up", "down", "up"]);
    expect(told).toHaveLength(2);
  });

  it("opens a new stream with backoff when EventSource gives up", () => {
    stream();
    latest().fail();
    expect(told).toHaveLength(1); // maybe the session ended: the state says
    expect(FakeSource.opened).toHaveLength(1);
    vi.advanceTimersByTime(999);
    expect(FakeSource.opened).toHaveLength(1);
    vi.advanceTimersByTime(1);
    expect(FakeSource.opened).toHaveLength(2);
    latest().fail();
    vi.advanceTimersByTime(1999);
    expect(FakeSource.opened).toHaveLength(2);
    vi.advanceTimersByTime(1);
    expect(FakeSource.opened).toHaveLength(3);
    latest().open();
    latest().fail();
    vi.advanceTimersByTime(1000); // back to the first delay after a success
    expect(FakeSource.opened).toHaveLength(4);
  });

  it("reopens at once when the page shows again or the network is back", () => {
    const live = stream();
    latest().fail();
    live.wake();
    expect(FakeSource.opened).toHaveLength(2);
    expect(told).toHaveLength(2);
    latest().open();
    live.wake(); // an open stream is kept; only the state is fetched
    expect(FakeSource.opened).toHaveLength(2);
    expect(told).toHaveLength(4);
  });

  it("drops the stream when the browser says the network is gone, until woken", () => {
    const live = stream();
    const source = latest();
    source.open();
    live.drop();
    expect(source.closed).toBe(true);
    expect(statuses).toEqual(["up", "down"]);
    vi.advanceTimersByTime(60_000);
    expect(FakeSource.opened).toHaveLength(1); // nothing opened while offline
    live.wake();
    expect(FakeSource.opened).toHaveLength(2);
    latest().open();
    expect(statuses).toEqual(["up", "down", "up"]);
  });

  it("ends on 'expired' and opens nothing more", () => {
    stream();
    latest().open();
    latest().emit("expired");
    expect(ended).toBe(1);
    expect(latest().closed).toBe(true);
    vi.advanceTimersByTime(60_000);
    expect(FakeSource.opened).toHaveLength(1);
  });

  it("stops listening when stopped", () => {
    const live = stream();
    const source = latest();
    live.stop();
    expect(source.closed).toBe(true);
    source.emit("taps");
    live.wake();
    expect(told).toHaveLength(0);
    expect(FakeSource.opened).toHaveLength(1);
  });
});
