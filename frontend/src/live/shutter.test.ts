import { describe, expect, it } from "vitest";
import { fromEuler } from "./orientation";
import type { Sample } from "./sensor";
import { stillOrientation } from "./shutter";

function sample(at: number, alpha: number): Sample {
  return { at, device: fromEuler(alpha, 90, 0), screenAngle: 0 };
}

describe("the orientation at the shutter", () => {
  it("is the newest reading of a still phone", () => {
    const samples = [sample(0, 10), sample(700, 10.5), sample(900, 11)];
    expect(stillOrientation(samples, 1000)).toBe(samples[2]);
  });

  it("holds a reading sent long ago: a browser sends one only when it changes", () => {
    const samples = [sample(0, 10)];
    expect(stillOrientation(samples, 60_000)).toBe(samples[0]);
  });

  it("counts the reading in force when the window opened", () => {
    // Turned 5 degrees 100 ms before the shutter: the reading before it held until then.
    expect(stillOrientation([sample(0, 10), sample(900, 15)], 1000)).toBeNull();
    // ... but not one replaced before the window opened.
    const samples = [sample(0, 10), sample(300, 15), sample(900, 15.5)];
    expect(stillOrientation(samples, 1000)).toBe(samples[2]);
  });

  it("is none without a reading, or only with readings after the tap", () => {
    expect(stillOrientation([], 1000)).toBeNull();
    expect(stillOrientation([sample(1200, 10)], 1000)).toBeNull();
  });
});
