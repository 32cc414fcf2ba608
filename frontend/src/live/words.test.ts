import { describe, expect, it } from "vitest";
import { t } from "../i18n";
import { arrowLabel, pointingText } from "./words";

const CURVE_LIVE_TEXT = t("live.curve");
const LEVEL_LIVE_TEXT = t("live.level");
const FRAME_LIVE_TEXT = t("live.frame");

describe("what Show me says", () => {
  it("says where the friend is, or which way to turn", () => {
    expect(pointingText({ kind: "in-view", at: { x: 1, y: 2 } }, null)).toBe(FRAME_LIVE_TEXT);
    const off = { kind: "off-view", at: { x: 0, y: 0 }, angle: Math.PI, turn: "left" } as const;
    expect(pointingText(off, null)).toBe("Turn left: your friend is that way.");
    expect(arrowLabel(off)).toBe("turn left");
  });

  it("speaks of the curve when there is no point", () => {
    expect(pointingText(null, "curve")).toBe(CURVE_LIVE_TEXT);
    // The level from gravity in the tap screen's words: a band, on this level.
    expect(pointingText(null, "level")).toBe(LEVEL_LIVE_TEXT);
    expect(LEVEL_LIVE_TEXT).toMatch(/yellow band: on this level/);
    expect(pointingText(null, null)).toBe("");
    // Off the screen: which way to turn to the curve.
    const down = { kind: "off-view", at: { x: 0, y: 0 }, angle: Math.PI / 2, turn: "down" } as const;
    expect(pointingText(down, "level")).toBe("Turn down: the dotted curve your friend is on is that way.");
    expect(arrowLabel(down)).toBe("turn down");
  });
});
