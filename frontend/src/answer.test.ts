import { describe, expect, it } from "vitest";
import { CURVE_TEXT, describeAnswer, neededText, suspectIds } from "./answer";
import type { SessionState, SolveResult } from "./types";

function state(result: Partial<SolveResult> | null, extra: Partial<SessionState> = {}): SessionState {
  return {
    session_id: "s",
    you: "buddy",
    version: 9,
    expires_at: "",
    join_code: null,
    join_code_renewals: 0,
    join_url: null,
    participants: { seeker: { joined: true, online: true }, buddy: { joined: true, online: true } },
    photos: { seeker: { width: 640, height: 480, scale: 1 }, buddy: { width: 640, height: 480, scale: 1 } },
    taps: { seeker: null, buddy: null },
    landmarks_needed: 0,
    result:
      result === null
        ? null
        : {
            method: "five_point_epipole",
            landmark_count: 5,
            epipole2: [300, 200],
            epipole2_h: [0.8, 0.6, 0.001],
            epipole1: [10, 10],
            uncertainty: { level: 0.95, ellipse: { center: [300, 200], axes: [12, 5], angle_deg: 30 } },
            suspect_landmarks: [],
            quality: "good",
            warnings: [],
            ...result,
          },
    result_version: result === null ? null : 9,
    result_landmark_ids: [1, 2, 4, 5, 7],
    result_error: null,
    ...extra,
  };
}

describe("the answer on each phone", () => {
  it("is nothing before there is an answer", () => {
    expect(describeAnswer(state(null), "buddy").kind).toBe("none");
  });

  it("is the curve with 4 landmarks", () => {
    const view = describeAnswer(state({ method: "conic", epipole2: null, epipole2_h: null }), "buddy");
    expect(view.kind).toBe("curve");
    expect(view.text).toBe(CURVE_TEXT);
    expect(view.position).toBeNull();
    expect(view.hasOverlay).toBe(true);
  });

  it("is the position with its ellipse and quality on the buddy's phone", () => {
    const view = describeAnswer(state({}), "buddy");
    expect(view.kind).toBe("position");
    expect(view.position).toEqual({
      x: 300,
      y: 200,
      ellipse: { center: [300, 200], axes: [12, 5], angle_deg: 30 },
      quality: "good",
    });
    expect(view.text).toContain("star");
  });

  it("says to turn when the friend is outside the photo", () => {
    expect(describeAnswer(state({ epipole2: [900, 200] }), "buddy").text).toContain("arrow");
  });

  it("tells the seeker that the buddy can see them", () => {
    expect(describeAnswer(state({}), "seeker").text).toBe("Your buddy can now see where you are.");
  });

  it("says 'turn around' when the friend is behind", () => {
    const behind = describeAnswer(state({ epipole2: null, epipole2_h: [0.1, 0.1, -0.99] }), "buddy");
    expect(behind.kind).toBe("elsewhere");
    expect(behind.text).toContain("turn around");
  });

  it("names suspects by the numbers people see", () => {
    const view = describeAnswer(state({ suspect_landmarks: [1, 3], warnings: ["Re-check #2."] }), "buddy");
    expect(view.suspects).toEqual([2, 5]);
    expect(view.warnings).toEqual(["Re-check #2."]);
    expect(suspectIds(state({ suspect_landmarks: [9] }))).toEqual([]);
  });

  it("passes on the solver's refusal", () => {
    const refused = state(null, {
      result_error: { code: "collinear_landmarks", message: "All landmarks are on one line." },
    });
    const view = describeAnswer(refused, "buddy");
    expect(view.kind).toBe("refused");
    expect(view.text).toBe("All landmarks are on one line.");
  });

  it("counts the landmarks still needed", () => {
    expect(neededText(3)).toBe("3 more landmarks needed");
    expect(neededText(1)).toBe("1 more landmark needed");
    expect(neededText(0)).toContain("Enough");
  });
});
