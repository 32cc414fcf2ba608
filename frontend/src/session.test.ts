import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { FakeSource } from "./fixtures/eventSource";
import { answer, joinerAt7, taps } from "./fixtures/joiner";
import { stubLocalStorage } from "./fixtures/localStorage";
import { SessionController } from "./session";
import type { Taps } from "./types";

const AT_7 = joinerAt7();

describe("a phone in its session", () => {
  let calls: string[];
  let controller: SessionController;

  beforeEach(() => {
    vi.useFakeTimers();
    FakeSource.opened = [];
    calls = [];
    vi.stubGlobal("EventSource", FakeSource);
    vi.stubGlobal("document", { visibilityState: "visible", addEventListener: () => undefined, removeEventListener: () => undefined });
    vi.stubGlobal("window", { addEventListener: () => undefined, removeEventListener: () => undefined });
    stubLocalStorage();
    // The page's address: the API's requests are made against it (api.ts).
    vi.stubGlobal("location", { origin: "http://phone.test" });
    vi.stubGlobal("fetch", async (request: Request) => {
      const { method } = request;
      calls.push(`${method} ${new URL(request.url).pathname}`);
      const body = method === "PUT" ? { ...AT_7, version: 9, taps: { ...AT_7.taps, joiner: (await request.json()) as Taps } } : AT_7;
      return new Response(JSON.stringify(body), { status: 200, headers: { "Content-Type": "application/json" } });
    });
    controller = new SessionController({ session_id: "s", token: "t", role: "joiner" });
  });

  afterEach(() => {
    controller.stop();
    vi.unstubAllGlobals();
    vi.useRealTimers();
  });

  const stateReads = (): number => calls.filter((call) => call === "GET /api/sessions/s").length;

  async function live(): Promise<void> {
    controller.start();
    FakeSource.opened[0]?.open();
    await vi.advanceTimersByTimeAsync(0);
    expect(controller.view.state?.version).toBe(7);
  }

  it("draws the answer its event brings, reading no state", async () => {
    await live();
    const reads = stateReads();
    const stream = FakeSource.opened[0]!;
    stream.emit("taps", { role: "starter", version: 8, taps: taps(1, 2, 3, 4), landmarks_needed: 0 });
    stream.emit("answer", { version: 8, answer: answer(1, 2, 3, 4), answer_error: null, landmarks_needed: 0 });
    await vi.advanceTimersByTimeAsync(0);
    expect(controller.view.answerState?.answer?.landmark_ids).toEqual([1, 2, 3, 4]);
    expect(controller.view.state?.taps.starter).toEqual(taps(1, 2, 3, 4));
    expect(stateReads()).toBe(reads);
  });

  it("reads the state when it finds a change missing", async () => {
    await live();
    const reads = stateReads();
    FakeSource.opened[0]!.emit("answer", { version: 9, answer: answer(1, 2, 3, 4), answer_error: null, landmarks_needed: 0 });
    await vi.advanceTimersByTimeAsync(0);
    expect(stateReads()).toBe(reads + 1);
  });

  it("sends a placed tap at once", async () => {
    await live();
    controller.taps.setMode("landmark");
    controller.taps.tap({ x: 40, y: 40, sigma: 2 });
    await vi.advanceTimersByTimeAsync(0);
    expect(calls.filter((call) => call.startsWith("PUT "))).toEqual(["PUT /api/sessions/s/taps"]);
  });
});
