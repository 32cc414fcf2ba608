import { describe, expect, it } from "vitest";
import { takeIn, type Outcome } from "./changes";
import { answer, joinerAt7, taps } from "./fixtures/joiner";
import type { SessionState } from "./types";

const ANSWER = answer(1, 2, 3);

function applied(outcome: Outcome): SessionState {
  if (outcome.kind !== "applied") throw new Error(`not applied: ${outcome.kind}`);
  return outcome.state;
}

describe("an event taken into the state shown", () => {
  it("shows the other phone's taps, and their answer, with nothing fetched", () => {
    const before = joinerAt7();
    const tapped = applied(takeIn(before, { type: "taps", data: { role: "starter", version: 8, taps: taps(1, 2, 3, 4), landmarks_needed: 0 } }));
    expect(tapped.version).toBe(8);
    expect(tapped.taps.starter).toEqual(taps(1, 2, 3, 4));
    expect(tapped.taps.joiner).toEqual(taps(1, 2, 3));
    expect(tapped.answer).toBeNull(); // the answer of version 7 goes with it
    const better = answer(1, 2, 3, 4);
    const answered = applied(takeIn(tapped, { type: "answer", data: { version: 8, answer: better, answer_error: null, landmarks_needed: 0 } }));
    expect(answered).toEqual({ ...tapped, answer: better, answer_version: 8 });
    expect(before.version).toBe(7); // the state shown before is left as it was
  });

  it("tells each phone the refusal said to it", () => {
    const tapped = applied(takeIn(joinerAt7(), { type: "taps", data: { role: "starter", version: 8, taps: taps(1, 2, 3, 4), landmarks_needed: 0 } }));
    const refusal = { code: "collinear_landmarks", reason: "collinear_landmarks", photo: 1 } as const;
    const said = { starter: { ...refusal, message: "All landmarks in your photo lie..." }, joiner: { ...refusal, message: "All landmarks in your friend's photo lie..." } };
    const refused = applied(takeIn(tapped, { type: "answer", data: { version: 8, answer: null, answer_error: said, landmarks_needed: 1 } }));
    expect(refused.answer_error).toEqual(said.joiner);
    expect(refused.answer_version).toBeNull();
    expect(refused.landmarks_needed).toBe(1);
  });

  it("shows a new photo of the other phone, its taps gone", () => {
    const photo = { width: 2560, height: 1920, scale: 0.5, lens: null };
    const state = applied(takeIn(joinerAt7(), { type: "photo", data: { role: "starter", version: 8, photo, landmarks_needed: 3 } }));
    expect(state.photos.starter).toEqual(photo);
    expect(state.taps.starter).toBeNull();
    expect(state.landmarks_needed).toBe(3);
    expect(state.answer).toBeNull();
  });

  it("shows the joiner joined on the starter's phone, its code used up", () => {
    const starter = joinerAt7({ you: "starter", join_code: "12345678", join_url: "http://x/join/12345678", participants: { starter: { joined: true, online: true }, joiner: { joined: false, online: false } } });
    const state = applied(takeIn(starter, { type: "joined", data: { role: "joiner", online: false, version: 8 } }));
    expect(state.participants.joiner).toEqual({ joined: true, online: false });
    expect([state.join_code, state.join_url, state.version]).toEqual([null, null, 8]);
  });

  it("shows a phone coming and going without a new version", () => {
    const gone = applied(takeIn(joinerAt7(), { type: "left", data: { role: "starter", online: false, version: null } }));
    expect(gone.participants.starter).toEqual({ joined: true, online: false });
    expect(gone.version).toBe(7);
    expect(gone.answer).toEqual(ANSWER);
    expect(takeIn(gone, { type: "left", data: { role: "starter", online: false, version: null } }).kind).toBe("shown");
  });

  it("is shown already when the state is at its version: the phone's own change", () => {
    const mine = joinerAt7();
    expect(takeIn(mine, { type: "taps", data: { role: "joiner", version: 7, taps: taps(1, 2, 3), landmarks_needed: 0 } }).kind).toBe("shown");
    expect(takeIn(mine, { type: "answer", data: { version: 7, answer: ANSWER, answer_error: null, landmarks_needed: 0 } }).kind).toBe("shown");
    expect(takeIn(mine, { type: "answer", data: { version: 6, answer: ANSWER, answer_error: null, landmarks_needed: 0 } }).kind).toBe("shown");
    expect(takeIn(mine, { type: "code", data: { renewed: true, version: 5 } }).kind).toBe("shown");
  });

  it("is fetched when a version is missing: the phone missed a change", () => {
    const shown = joinerAt7();
    expect(takeIn(shown, { type: "taps", data: { role: "starter", version: 9, taps: taps(1), landmarks_needed: 2 } }).kind).toBe("fetch");
    expect(takeIn(shown, { type: "answer", data: { version: 8, answer: ANSWER, answer_error: null, landmarks_needed: 0 } }).kind).toBe("fetch");
    expect(takeIn(shown, { type: "joined", data: { role: "joiner", online: false, version: 9 } }).kind).toBe("fetch");
  });

  it("is fetched when the event cannot tell, or nothing is shown yet", () => {
    const shown = joinerAt7();
    // Overtaken by another change: the count is the state's to say.
    expect(takeIn(shown, { type: "taps", data: { role: "starter", version: 8, taps: taps(1), landmarks_needed: null } }).kind).toBe("fetch");
    expect(takeIn(shown, { type: "code", data: { renewed: true, version: 8 } }).kind).toBe("fetch"); // codes go in no event
    expect(takeIn(shown, { type: "photo", data: null }).kind).toBe("fetch"); // not JSON
    expect(takeIn(shown, { type: "taps", data: { role: "starter" } }).kind).toBe("fetch");
    expect(takeIn(null, { type: "taps", data: { role: "starter", version: 1, taps: taps(1), landmarks_needed: 2 } }).kind).toBe("fetch");
  });
});
