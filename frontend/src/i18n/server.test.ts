import { afterAll, describe, expect, it } from "vitest";
import { ApiError } from "../api";
import type { Refusal, SolverWarning } from "../types";
import { speak } from "./index";
import de from "./locales/de.json";
import en from "./locales/en.json";
import { errorText, refusalText, warningText } from "./server";

describe("the server's sentences, by code", () => {
  afterAll(async () => {
    await speak("en", en);
  });

  it("words a warning from its code and parameters, numbers as the language writes them", async () => {
    const outside: SolverWarning = { code: "outside_photo", distance_px: 1234.6, side: "left", message: "Server words." };
    expect(warningText(outside)).toBe("Your friend is outside this photo, about 1,235 px beyond its left edge: turn left.");
    await speak("de", de);
    expect(warningText(outside)).toBe(
      "Dein Freund ist außerhalb dieses Fotos, etwa 1.235 px jenseits des linken Rands: Dreh dich nach links.",
    );
    await speak("en", en);
  });

  it("names the photos of a refusal for the phone it is said to", () => {
    const refusal: Refusal = { code: "repeated_landmarks", reason: "repeated_landmarks", photo: 2, landmarks: [2, 5], message: "" };
    expect(refusalText({ ...refusal, reader: 2 })).toBe(
      "Landmarks #2 and #5 are at the same place in your photo; each landmark must be a different spot.",
    );
    expect(refusalText({ ...refusal, reader: 1 })).toContain("in your friend's photo");
    const few: Refusal = { code: "too_few_landmarks", reason: "too_few_landmarks", count: 1, minimum: 3, marked: "point", message: "" };
    expect(refusalText({ ...few, reader: 1 })).toBe("1 landmark marked; at least 3 are needed with your friend marked.");
  });

  it("words a refused request by its code; the server's sentence only for a code it lacks", () => {
    expect(errorText(new ApiError(404, "invalid_join_code", "Server words."))).toContain("ask your friend for a new one");
    expect(errorText(new ApiError(0, "network", "Server words."))).toBe(en.error.network);
    expect(errorText(new ApiError(418, "from_a_newer_server", "Server words."))).toBe("Server words.");
    expect(errorText(new ApiError(502, "http_502", ""))).toBe("The server had a problem; try again.");
  });
});

