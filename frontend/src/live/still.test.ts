import { describe, expect, it } from "vitest";
import { fromEuler } from "./orientation";
import type { Sample } from "./sensor";
import { STILL_WAIT_MS, StillWait, turnRate, type Look } from "./still";

/** The upright phone turned `alpha` degrees about the vertical at `at` ms. */
function sample(at: number, alpha: number): Sample {
  return { at, device: fromEuler(alpha, 90, 0), screenAngle: 0 };
}

/** Readings every 16 ms of a phone turning `rate(t)` degrees a second (t ms), as a browser
 * sends them: only when the orientation changes. */
function readings(until: number, rate: (t: number) => number): Sample[] {
  const out: Sample[] = [];
  let alpha = 0;
  for (let at = 0; at <= until; at += 16) {
    const turn = (rate(at) * 16) / 1000;
    alpha += turn;
    if (turn !== 0 || out.length === 0) out.push(sample(at, alpha));
  }
  return out;
}

/** Align tapped at `tap` ms, the view looking every 33 ms: what it does and when. */
function align(samples: Sample[], tap: number): { look: Look; at: number; kept: number[] } {
  const wait = new StillWait(tap);
  const kept: number[] = [];
  for (let now = tap; ; now += 33) {
    const look = wait.look(now, turnRate(samples, now));
    if (look === "keep") kept.push(now);
    if (look === "send" || look === "best") return { look, at: now, kept };
  }
}

describe("the phone's turn rate", () => {
  it("is the turn over the last 300 ms", () => {
    const turning = readings(2000, () => 20);
    expect(turnRate(turning, 1000)).toBeCloseTo(20, 0);
    expect(turnRate([], 1000)).toBeNull();
  });

  it("holds a reading sent long ago: a still phone sends none", () => {
    expect(turnRate([sample(0, 10)], 60_000)).toBe(0);
    // Stopped 100 ms ago after turning: not still yet.
    const stopped = readings(1000, (t) => (t < 900 ? 30 : 0));
    expect(turnRate(stopped, 1000)).toBeGreaterThan(3);
    expect(turnRate(stopped, 1250)).toBe(0);
  });
});

describe("the frame Align sends", () => {
  it("is the frame of the tap when the phone is still", () => {
    const still = readings(3000, () => 0);
    expect(align(still, 1000)).toMatchObject({ look: "send", at: 1000 });
  });

  it("waits for the turning phone to hold still", () => {
    // Turning 30 degrees a second until 1.2 s, then still: sent once still for 300 ms.
    const settling = readings(4000, (t) => (t < 1200 ? 30 : 0));
    const { look, at } = align(settling, 1000);
    expect(look).toBe("send");
    expect(at).toBeGreaterThanOrEqual(1200 + 300 - 20);
    expect(at).toBeLessThan(1200 + 300 + 50);
  });

  it("sends the stillest frame seen when the phone never holds still", () => {
    // A hand that sways: 20 degrees a second, slowing to 8 at about 0.6 s after the tap.
    const swaying = readings(4000, (t) => (Math.abs(t - 1600) < 150 ? 8 : 20));
    const { look, at, kept } = align(swaying, 1000);
    expect(look).toBe("best");
    expect(at).toBeGreaterThanOrEqual(1000 + STILL_WAIT_MS);
    expect(at).toBeLessThan(1000 + STILL_WAIT_MS + 33);
    // The last frame kept was the slowest moment's.
    const last = kept[kept.length - 1] ?? 0;
    expect(Math.abs(last - 1700)).toBeLessThan(150);
    expect(turnRate(swaying, last)).toBeLessThan(12);
  });

  it("sends the frame of the moment when it is the stillest at the end of the wait", () => {
    const wait = new StillWait(0);
    expect(wait.look(0, 20)).toBe("keep");
    expect(wait.look(1000, 25)).toBe("wait");
    expect(wait.look(1500, 10)).toBe("send");
    expect(new StillWait(0).look(1500, null)).toBe("send");
  });
});
