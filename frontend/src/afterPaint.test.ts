import { afterEach, describe, expect, it, vi } from "vitest";
import { afterPaint } from "./afterPaint";

describe("afterPaint", () => {
  afterEach(() => {
    vi.useRealTimers();
    vi.unstubAllGlobals();
  });

  it("runs the work once, behind the frame, as a background task where the browser has one", () => {
    vi.useFakeTimers();
    const frames: FrameRequestCallback[] = [];
    const posted: { task: () => void; priority: string }[] = [];
    vi.stubGlobal("requestAnimationFrame", (callback: FrameRequestCallback) => frames.push(callback));
    vi.stubGlobal("scheduler", {
      postTask: (task: () => void, options: { priority: string }) => {
        posted.push({ task, priority: options.priority });
        return Promise.resolve();
      },
    });
    const work = vi.fn();
    afterPaint(work);
    expect(work).not.toHaveBeenCalled();
    frames.shift()?.(0); // the frame's callbacks: the work is posted, not run
    expect(work).not.toHaveBeenCalled();
    expect(posted.map((p) => p.priority)).toEqual(["background"]);
    posted[0]?.task();
    expect(work).toHaveBeenCalledTimes(1);
    vi.advanceTimersByTime(200); // the bound passes: nothing runs twice
    expect(work).toHaveBeenCalledTimes(1);
  });

  it("runs the work as the next task after the frame without a scheduler, and within the bound with no frame", () => {
    vi.useFakeTimers();
    const frames: FrameRequestCallback[] = [];
    vi.stubGlobal("requestAnimationFrame", (callback: FrameRequestCallback) => frames.push(callback));
    vi.stubGlobal("scheduler", undefined);
    const work = vi.fn();
    afterPaint(work);
    frames.shift()?.(0);
    vi.advanceTimersByTime(0);
    expect(work).toHaveBeenCalledTimes(1);

    const unpainted = vi.fn();
    afterPaint(unpainted, 100); // a hidden page: no frame comes
    vi.advanceTimersByTime(99);
    expect(unpainted).not.toHaveBeenCalled();
    vi.advanceTimersByTime(1);
    expect(unpainted).toHaveBeenCalledTimes(1);
  });
});
