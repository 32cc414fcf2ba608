import { describe, expect, it } from "vitest";
import { chooseLanguage } from "./languages";

describe("chooseLanguage", () => {
  it("takes the first of the phone's languages the app has, by its base", () => {
    expect(chooseLanguage(["nl-NL", "de-AT", "en-US"], null)).toBe("de");
    expect(chooseLanguage(["ja"], null)).toBe("ja");
  });

  it("keeps the person's own choice over the phone's", () => {
    expect(chooseLanguage(["de-DE"], "es")).toBe("es");
  });

  it("falls back to English for languages it lacks and for a stale choice", () => {
    expect(chooseLanguage(["nl-NL", "pt-BR"], "xx")).toBe("en");
    expect(chooseLanguage([], null)).toBe("en");
  });
});
