import { describe, expect, it } from "vitest";
import { describeAnswer, surenessText } from "./answer";
import { answer, joinerAt7 } from "./fixtures/joiner";
import { t } from "./i18n";

const CURVE_TEXT = t("answer.curve");
const LEVEL_TEXT = t("answer.level");
const COMPASS_TEXT = t("answer.compass");
const FRAME_TEXT = t("answer.frame");
const OUTSIDE_TEXT = t("answer.outside");
const WAVE_TEXT = t("answer.wave");
import type { Answer, FriendInPhoto, SessionState, SolverWarning } from "./types";

const RING = { center: [300, 200] as [number, number], axes: [12, 5] as [number, number], angle_deg: 30 };

/** The server's drawing on a 640 x 480 photo: what the sureness is measured in (a person far
 * across the hall, px). */
const DRAWING = { width: 640, height: 480, person: 800 / 55 };

/** Where each phone's friend is in its own photo: the starter marked, the joiner was told. */
function inPhoto(starter: Partial<FriendInPhoto> = {}, joiner: Partial<FriendInPhoto> = {}): Answer["in_photo"] {
  return {
    starter: { how: "marked", friend: [10, 10], friend_h: [0.1, 0.1, 0.01], ...starter },
    joiner: { how: "solved", friend: [300, 200], friend_h: [0.8, 0.6, 0.001], region: RING, drawing: DRAWING, ...joiner },
  };
}

function state(in_photo: Answer["in_photo"] | null, extra: Partial<SessionState> = {}): SessionState {
  return joinerAt7({
    version: 9,
    expires_at: "",
    taps: { starter: null, joiner: null },
    answer: in_photo && { ...answer(1, 2, 4, 5, 7), method: "five_point_epipole", suspects: [], in_photo },
    answer_version: in_photo === null ? null : 9,
    ...extra,
  });
}

describe("the answer on each phone", () => {
  it("is nothing before there is an answer", () => {
    expect(describeAnswer(state(null), "joiner").kind).toBe("none");
  });

  it("is the curve with 4 landmarks", () => {
    const view = describeAnswer(state(inPhoto({}, { friend: null, friend_h: null, region: null, curve: [[1, 0, 0], [0, 1, 0], [0, 0, -1]] })), "joiner");
    expect(view.kind).toBe("curve");
    expect(view.text).toBe(CURVE_TEXT);
    expect(view.position).toBeNull();
    expect(view.curve).toEqual([[1, 0, 0], [0, 1, 0], [0, 0, -1]]);
  });

  it("is the level from both phones' gravity, with no landmark", () => {
    const level: [number, number][][] = [[[0, 400], [640, 380]]];
    const view = describeAnswer(state(inPhoto({}, { friend: null, friend_h: null, region: null, level, level_halfwidth: 30 })), "joiner");
    expect(view.kind).toBe("curve");
    expect(view.text).toBe(LEVEL_TEXT);
    expect(view.position).toBeNull();
    expect(describeAnswer(state(inPhoto({}, { friend: null, friend_h: null, region: null, level })), "starter").seen).toBe(true);
  });

  it("does not say twice what the curve's headline says, and keeps the other warnings", () => {
    const said = (code: SolverWarning["code"]): SolverWarning => ({ code, message: `server: ${code}` });
    const warnings = [said("on_the_curve"), said("on_the_level"), said("camera_model_disagrees")];
    const curve = describeAnswer(state(inPhoto({}, { friend: null, friend_h: null, region: null, curve: [[1, 0, 0], [0, 1, 0], [0, 0, -1]], warnings })), "joiner");
    const level = describeAnswer(state(inPhoto({}, { friend: null, friend_h: null, region: null, level: [[[0, 400], [640, 380]]], warnings })), "joiner");
    const point = describeAnswer(state(inPhoto({}, { warnings })), "joiner");
    for (const view of [curve, level]) {
      expect(view.warnings).toHaveLength(1);
      expect(view.warnings[0]).toMatch(/phone photos/);
    }
    expect(point.warnings).toHaveLength(3); // a point: nothing in its headline says them
  });

  it("is the level with the stretch the compasses point to, worded as a hint", () => {
    const level: [number, number][][] = [[[0, 400], [640, 380]]];
    const curve = { polylines: level, label_at: [320, 360] as [number, number], text: "", halfwidth: 30 };
    const bare = describeAnswer(state(inPhoto({}, { friend: null, friend_h: null, region: null, level, drawing: { ...DRAWING, curve } })), "joiner");
    expect(bare.text).toBe(LEVEL_TEXT);
    const stretch: [number, number][][] = [[[200, 392], [330, 386]]];
    const hinted = { ...DRAWING, curve: { ...curve, stretch } };
    const view = describeAnswer(state(inPhoto({}, { friend: null, friend_h: null, region: null, level, level_stretch: stretch, drawing: hinted })), "joiner");
    expect(view.kind).toBe("curve");
    expect(view.text).toBe(COMPASS_TEXT);
    expect(view.text).toMatch(/compass points .*a hint, steel bends compasses/);
    expect(view.drawing?.curve?.stretch).toEqual(stretch);
  });

  it("is the position found, with its region, on the phone that did not mark", () => {
    const view = describeAnswer(state(inPhoto()), "joiner");
    expect(view.kind).toBe("position");
    expect(view.position).toEqual({ x: 300, y: 200, ellipse: RING, quality: "good", how: "solved" });
    expect(view.text).toBe(FRAME_TEXT); // what is drawn: a frame, labelled "friend"
    expect(view.text).not.toMatch(/star|ring/);
    expect(view.news).toBe(true); // brought into view
    expect(view.sureness).toMatch(/^Good: /);
    expect(view.sureness).not.toMatch(/px/);
    expect(view.seen).toBe(false);
  });

  it("is the same found by either phone: the roles only say who started", () => {
    const swapped = { starter: inPhoto().joiner, joiner: inPhoto().starter } as Answer["in_photo"];
    expect(describeAnswer(state(swapped), "starter")).toEqual(describeAnswer(state(inPhoto()), "joiner"));
    expect(describeAnswer(state(swapped), "joiner")).toEqual(describeAnswer(state(inPhoto()), "starter"));
  });

  it("tells the phone that marked its friend that the friend can now see them", () => {
    const view = describeAnswer(state(inPhoto()), "starter");
    expect(view.seen).toBe(true);
    expect(view.text).toBe(WAVE_TEXT);
    expect(view.position).toMatchObject({ x: 10, y: 10, how: "marked", ellipse: null });
    expect(view.news).toBe(false); // its own mark: nothing new to bring into view
  });

  it("shows each phone its own mark, refined, when both marked each other", () => {
    const both = inPhoto({}, { how: "marked" });
    for (const role of ["starter", "joiner"] as const) {
      const view = describeAnswer(state(both), role);
      expect(view.text).toContain("You marked each other");
      expect(view.position?.how).toBe("marked");
      expect(view.seen).toBe(false);
    }
    expect(describeAnswer(state(both), "joiner").position?.ellipse).toEqual(RING);
  });

  it("names the point a line gave", () => {
    const view = describeAnswer(state(inPhoto({ how: "on_line" })), "starter");
    expect(view.text).toContain("on your line");
    expect(view.position?.how).toBe("on_line");
  });

  it("says to turn when the friend is outside the photo", () => {
    const view = describeAnswer(state(inPhoto({}, { friend: [900, 200] })), "joiner");
    expect(view.text).toBe(OUTSIDE_TEXT);
  });

  it("asks for a mark when there is a point but no sure region", () => {
    const view = describeAnswer(state(inPhoto({}, { region: null })), "joiner");
    expect(view.text).toContain("most likely");
    expect(view.news).toBe(true);
  });

  it("says 'turn around' when the friend is behind", () => {
    const view = describeAnswer(state(inPhoto({}, { friend: null, friend_h: [0.1, 0.1, -0.99], region: null })), "joiner");
    expect(view.kind).toBe("elsewhere");
    expect(view.text).toContain("turn around");
  });

  it("passes on the warnings said to this phone, and the suspects by number", () => {
    const misfit: SolverWarning = { code: "misfit", photo: 1, landmark: 2, message: "#2 does not fit the others: check it in both photos." };
    const uncertain: SolverWarning = { code: "uncertain", photo: 2, message: "The position is uncertain." };
    // About both photos: the server says it to both, worded once (shared_solver/words.py).
    const compasses: SolverWarning = { code: "heading_disagrees", message: "The phones' compasses do not fit these marks." };
    const answer = state(inPhoto({ warnings: [compasses, misfit] }, { warnings: [compasses, uncertain] }));
    if (answer.answer) answer.answer.suspects = [2, 5];
    // Each in the catalogue's words for its code and parameters, not the server's sentence.
    const heading = t("warning.heading_disagrees");
    expect(describeAnswer(answer, "starter").warnings).toEqual([heading, misfit.message]);
    expect(describeAnswer(answer, "joiner").warnings).toEqual([heading, t("warning.uncertain")]);
    expect(describeAnswer(answer, "joiner").suspects).toEqual([2, 5]);
  });

  it("keeps the server's sentence for a warning code the catalogue does not know", () => {
    const newer = { code: "from_a_newer_server", message: "Something new." } as unknown as SolverWarning;
    expect(describeAnswer(state(inPhoto({ warnings: [newer] }, {})), "starter").warnings).toEqual(["Something new."]);
  });

  it("passes on the solver's refusal", () => {
    const refused = state(null, {
      answer_error: {
        code: "collinear_landmarks",
        reason: "collinear_landmarks",
        photo: 2,
        message: "All landmarks in your photo lie on one straight line; add landmarks off that line.",
      },
    });
    const view = describeAnswer(refused, "joiner");
    expect(view.kind).toBe("refused");
    // An older server says no reader: its own sentence, which names the photos for this phone.
    expect(view.text).toBe("All landmarks in your photo lie on one straight line; add landmarks off that line.");
    const error = refused.answer_error;
    if (error) refused.answer_error = { ...error, reader: 1, message: "" };
    expect(describeAnswer(refused, "starter").text).toBe(
      "All landmarks in your friend's photo lie on one straight line; add landmarks off that line.",
    );
  });

  it("says how sure the frame is in people, never in pixels", () => {
    // A person far across the hall, px, as the answer's drawing says it.
    const person = 800 / 55;
    const region = (across: number) => ({ center: [0, 0] as [number, number], axes: [across / 2, 2] as [number, number], angle_deg: 0 });
    expect(surenessText(region(person), "good", person)).toBe("Good: the frame is about one person across.");
    expect(surenessText(region(5 * person), "good", person)).toBe("Rough: the frame is about 5 people across.");
    expect(surenessText(region(person), "poor", person)).toMatch(/^Rough: /);
    expect(surenessText(null, "good", person)).toMatch(/^Rough: no sure region/);
  });
});
