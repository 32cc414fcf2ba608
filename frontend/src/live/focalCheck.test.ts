import { describe, expect, it } from "vitest";
import { AGREE_DEG, CHECK_WITHIN_DEG, agrees, checkNow } from "./focalCheck";
import { fromEuler, multiply, transpose, type Matrix3 } from "./orientation";
import { STILL_RATE_DEG_S } from "./still";

/** A turn of `degrees` about the camera's vertical (y), as the upright phone turns. */
function aboutVertical(degrees: number): Matrix3 {
  // DeviceOrientation's alpha turns the upright phone about the world's vertical; the
  // turn between two such readings is one about the camera's y.
  return multiply(transpose(fromEuler(degrees, 90, 0)), fromEuler(0, 90, 0));
}

describe("the quiet check of the video's focal length", () => {
  it("sends once, from a still phone facing its photo's view", () => {
    expect(checkNow("waiting", 0.5, 5)).toBe(true);
    expect(checkNow("waiting", STILL_RATE_DEG_S + 1, 5)).toBe(false); // turning
    expect(checkNow("waiting", null, 5)).toBe(false); // no rate yet
    expect(checkNow("waiting", 0.5, CHECK_WITHIN_DEG + 1)).toBe(false); // facing elsewhere
    for (const over of ["off", "sending", "measured", "refused", "disagreed"] as const) {
      expect(checkNow(over, 0.5, 5)).toBe(false);
    }
  });

  it("keeps a match that agrees with the sensors, not one that does not", () => {
    const sensed = aboutVertical(10);
    expect(agrees(aboutVertical(10.3), sensed)).toBe(true);
    expect(agrees(aboutVertical(10 + AGREE_DEG - 0.1), sensed)).toBe(true);
    expect(agrees(aboutVertical(10 + AGREE_DEG + 0.1), sensed)).toBe(false);
    expect(agrees(aboutVertical(-10), sensed)).toBe(false); // the other way round
  });
});
