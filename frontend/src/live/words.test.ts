import { describe, expect, it } from "vitest";
import { t } from "../i18n";
import { arrowLabel, pointingText } from "./words";

const CURVE_LIVE_TEXT = t("live.curve");
const FRAME_LIVE_TEXT = t("live.frame");

describe("what Show me says", () => {
  it("says where the friend is, or which way to turn", () => {
    expect(pointingText({ kind: "in-view", at: { x: 1, y: 2 } }, false)).toBe(FRAME_LIVE_TEXT);
    const off = { kind: "off-view", at: { x: 0, y: 0 }, angle: Math.PI, turn: "left" } as const;
    expect(pointingText(off, false)).toBe("Turn left: your friend is that way.");
    expect(arrowLabel(off)).toBe("turn left");
  });

  it("speaks of the curve when there is no point", () => {
    expect(pointingText(null, true)).toBe(CURVE_LIVE_TEXT);
    expect(pointingText(null, false)).toBe("");
    // Off the screen: which way to turn to the curve.
    const down = { kind: "off-view", at: { x: 0, y: 0 }, angle: Math.PI / 2, turn: "down" } as const;
    expect(pointingText(down, true)).toBe("Turn down: the dotted curve your friend is on is that way.");
    expect(arrowLabel(down)).toBe("turn down");
  });
});
