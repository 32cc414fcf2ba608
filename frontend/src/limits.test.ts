import { describe, expect, it } from "vitest";
import limitsJson from "../../backend/limits.json?raw";
import { CODE_DIGITS, EVENTS, MAX_LANDMARK_ID, MAX_LANDMARKS, STORED_PHOTO_SIDE, TAP_PRECISION } from "./limits";
import { CHANGE_EVENTS, ENDED_EVENT } from "./reconnect";

// The file as written, which backend/limits.py reads too: the one source.
const source = JSON.parse(limitsJson) as Record<string, unknown>;

describe("the limits the phone shares with the server", () => {
  it("are backend/limits.json's", () => {
    expect(STORED_PHOTO_SIDE).toBe(source.stored_photo_side);
    expect(MAX_LANDMARKS).toBe(source.max_landmarks);
    expect(MAX_LANDMARK_ID).toBe(source.max_landmark_id);
    expect(CODE_DIGITS).toBe(source.join_code_length);
    expect(EVENTS).toEqual(source.events);
    expect(TAP_PRECISION).toEqual(source.tap_precision);
  });

  it("name every event the stream carries: the end, and changes", () => {
    expect([...CHANGE_EVENTS, ENDED_EVENT].sort()).toEqual([...(source.events as string[])].sort());
    expect(CHANGE_EVENTS).toContain("answer");
  });
});
