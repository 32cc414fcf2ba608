import { describe, expect, it } from "vitest";
import { nextStep, type StepInput } from "./nextStep";

function input(extra: Partial<StepInput>): StepInput {
  return {
    mine: [],
    theirs: [],
    skipped: new Set(),
    needed: 3,
    theirPhoto: true,
    iMarked: false,
    theyMarked: false,
    toldWhere: false,
    seen: false,
    ...extra,
  };
}

describe("this phone's next step", () => {
  it("asks the phone that marked its friend for its own count of landmarks", () => {
    const step = nextStep(input({ iMarked: true, mine: [1], needed: 3 }));
    // #1 is tapped here and not yet found there: 2 more to tap here, not 3.
    expect(step).toMatchObject({ title: "Tap 2 more landmarks", kind: "tap", toTap: 2 });
    expect(nextStep(input({ iMarked: true, mine: [1, 2], needed: 3 })).title).toBe("Tap 1 more landmark");
  });

  it("waits for the friend to find this phone's landmarks once it tapped enough", () => {
    const step = nextStep(input({ iMarked: true, mine: [1, 2, 3, 4, 5, 6], theirs: [1, 2], needed: 1 }));
    expect(step).toMatchObject({ title: "Waiting for your friend to find #3", kind: "wait", toTap: 0 });
  });

  it("asks the other phone to find the friend's landmarks, with its own count", () => {
    const step = nextStep(input({ theyMarked: true, theirs: [1, 2, 3], mine: [1], needed: 2 }));
    expect(step).toMatchObject({ title: "Find #2 here", kind: "find", toTap: 2 });
  });

  it("waits for the friend who marked this phone's owner to tap the first landmark", () => {
    const step = nextStep(input({ theyMarked: true, needed: 3 }));
    expect(step.title).toBe("Waiting for your friend to tap #1");
    expect(step.title).not.toMatch(/Tap a landmark/);
  });

  it("says the friend is taking their photo before they have one", () => {
    expect(nextStep(input({ theirPhoto: false, iMarked: true })).title).toBe("Your friend is taking their photo");
  });

  it("stops asking for landmarks once there is an answer", () => {
    const seen = nextStep(input({ iMarked: true, mine: [1, 2, 3], theirs: [1, 2, 3], needed: 0, seen: true }));
    expect(seen).toMatchObject({ title: "Your friend sees where you are.", kind: "done", toTap: 0 });
    expect(seen.detail).toBe("Add a landmark to sharpen it.");
    const told = nextStep(input({ mine: [1, 2, 3], theirs: [1, 2, 3], needed: 0, toldWhere: true }));
    expect(told).toMatchObject({ title: "Done", kind: "done" });
    // The friend tapped one more: finding it sharpens the answer, no count.
    const more = nextStep(input({ mine: [1, 2, 3], theirs: [1, 2, 3, 4], needed: 0, toldWhere: true }));
    expect(more).toMatchObject({ title: "Find #4 here", kind: "find", toTap: 0 });
  });

  it("never counts the friend's landmarks as this phone's to tap", () => {
    for (let mine = 0; mine <= 7; mine++) {
      const ids = Array.from({ length: mine }, (_, i) => i + 1);
      const step = nextStep(input({ iMarked: true, mine: ids, needed: 3 }));
      expect(step.toTap).toBe(Math.max(0, 3 - mine));
    }
  });
});
