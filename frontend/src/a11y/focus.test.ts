import { describe, expect, it } from "vitest";
import { answerFocusKey } from "./focus";

describe("answerFocusKey", () => {
  it("is none before an answer, and changes with the answer's kind or how it was found", () => {
    expect(answerFocusKey("none", null)).toBeNull();
    expect(answerFocusKey("position", "solved")).toBe("position:solved");
    expect(answerFocusKey("position", "marked")).not.toBe(answerFocusKey("position", "solved"));
    expect(answerFocusKey("curve", null)).not.toBe(answerFocusKey("position", "solved"));
  });
});
