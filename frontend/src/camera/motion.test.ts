import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { GRAVITY } from "./gravity";
import { COMPASS_SIGMA_DEG } from "./heading";
import { cameraProblem, sensorFields, stillnessWords } from "./InAppCamera";
import type { MotionRecorder } from "./motion";

/** motion.ts afresh (its answer is kept per page). */
async function motion(): Promise<typeof import("./motion")> {
  vi.resetModules();
  return import("./motion");
}

afterEach(() => {
  vi.unstubAllGlobals();
  vi.useRealTimers();
});

describe("the motion question (iOS)", () => {
  it("is asked where the browser asks, once: the answer is kept", async () => {
    const requestPermission = vi.fn(() => Promise.resolve("denied"));
    vi.stubGlobal("DeviceMotionEvent", { requestPermission });
    const { answerMotion, motionAccess } = await motion();
    expect(motionAccess()).toBe("ask");
    expect(await answerMotion(true)).toBe("denied");
    expect(motionAccess()).toBe("denied");
    expect(requestPermission).toHaveBeenCalledTimes(1);
  });

  it("is not asked of the system after Not now", async () => {
    const requestPermission = vi.fn(() => Promise.resolve("granted"));
    vi.stubGlobal("DeviceMotionEvent", { requestPermission });
    const { answerMotion, motionAccess } = await motion();
    expect(await answerMotion(false)).toBe("denied");
    expect(motionAccess()).toBe("denied");
    expect(requestPermission).not.toHaveBeenCalled();
  });

  it("counts a question that fails (not from a tap, not over HTTPS) as a no", async () => {
    vi.stubGlobal("DeviceMotionEvent", { requestPermission: () => Promise.reject(new Error("NotAllowedError")) });
    const { answerMotion } = await motion();
    expect(await answerMotion(true)).toBe("denied");
  });

  it("is not asked where the browser does not ask (Android, desktop)", async () => {
    vi.stubGlobal("DeviceMotionEvent", function DeviceMotionEvent() {});
    const { motionAccess } = await motion();
    expect(motionAccess()).toBe("granted");
  });
});

describe("the accelerometer while the camera is open", () => {
  let page: EventTarget;

  beforeEach(() => {
    vi.useFakeTimers({ toFake: ["performance"] });
    page = new EventTarget();
    vi.stubGlobal("window", page);
    vi.stubGlobal("screen", { orientation: { angle: 90 } });
  });

  /**
   * Motion events every 20 ms for `ms`, reading `reading(k)`; with `orientation`, an absolute
   * orientation event (alpha, beta, gamma) beside each.
   */
  function shake(
    reading: (k: number) => [number, number, number] | null,
    ms = 500,
    orientation: [number, number, number] | null = null,
  ): void {
    for (let k = 0; k * 20 < ms; k += 1) {
      vi.advanceTimersByTime(20);
      const a = reading(k);
      const event = Object.assign(new Event("devicemotion"), {
        accelerationIncludingGravity: a ? { x: a[0], y: a[1], z: a[2] } : { x: null, y: null, z: null },
      });
      page.dispatchEvent(event);
      if (orientation) {
        const [alpha, beta, gamma] = orientation;
        page.dispatchEvent(Object.assign(new Event("deviceorientationabsolute"), { alpha, beta, gamma, absolute: true }));
      }
    }
  }

  /** A new page's recorder, started. */
  async function recording(): Promise<MotionRecorder> {
    const recorder = new (await motion()).MotionRecorder();
    recorder.start();
    return recorder;
  }

  it("reads down in the photo from a still phone, for the screen's turn", async () => {
    const recorder = await recording();
    shake(() => [GRAVITY, 0, 0]); // landscape, turned anticlockwise, level
    const reading = recorder.reading();
    expect(reading.kind === "still" && reading.gravity).toEqual([0, 1, 0]);
    expect(sensorFields(reading, recorder.heading())).toEqual({ gravity: [0, 1, 0], gravity_sigma_deg: 1 });
    expect(stillnessWords("granted", reading)).toMatch(/is known/);
  });

  it("reads the lens's heading beside down where the phone has an absolute orientation", async () => {
    const recorder = await recording();
    // On its side (its right edge up: the reading above), level, looking east, its top to the
    // north: turned -90 degrees about its top from flat (a hair off, where the angles lock).
    shake(() => [GRAVITY, 0, 0], 500, [0, 0, -89.9]);
    const heading = recorder.heading();
    expect(heading.kind === "still" && heading.heading).toBeCloseTo(90, 6);
    expect(sensorFields(recorder.reading(), heading)).toEqual({
      gravity: [0, 1, 0],
      gravity_sigma_deg: 1,
      heading: heading.kind === "still" ? heading.heading : null,
      heading_sigma_deg: COMPASS_SIGMA_DEG,
    });
    // No heading without down: the solver has no use for one alone.
    expect(sensorFields({ kind: "moving" }, heading)).toBeNull();
    recorder.stop();
    shake(() => [GRAVITY, 0, 0], 500, [0, 0, -89.9]);
    expect(recorder.heading()).toEqual({ kind: "none" });
  });

  it("sends nothing from a phone that moves at the shutter, and says so", async () => {
    const recorder = await recording();
    shake((k) => [GRAVITY, k % 2 ? 3 : -3, 0]);
    const reading = recorder.reading();
    expect(reading).toEqual({ kind: "moving" });
    expect(sensorFields(reading, { kind: "still", heading: 10, sigmaDeg: 15 })).toBeNull();
    expect(stillnessWords("granted", reading)).toMatch(/Hold the phone still/);
  });

  it("reads nothing once stopped, nor from a browser without a sensor", async () => {
    const recorder = await recording();
    shake(() => null);
    expect(recorder.reading()).toEqual({ kind: "none" });
    recorder.stop();
    shake(() => [GRAVITY, 0, 0]);
    expect(recorder.reading()).toEqual({ kind: "none" });
  });
});

describe("the camera's words", () => {
  it("says why the camera did not open, with the other two choices", () => {
    const refused = cameraProblem(new DOMException("denied", "NotAllowedError"));
    expect(refused).toMatch(/not allowed/);
    expect(cameraProblem(new DOMException("none", "NotFoundError"))).toMatch(/No camera/);
    for (const words of [refused, cameraProblem(new Error("?"))]) expect(words).toMatch(/camera or choose one from the gallery/);
  });

  it("tells a person who refused motion access that the photo goes without down", () => {
    expect(stillnessWords("denied", { kind: "none" })).toMatch(/without which way is down/);
  });
});
