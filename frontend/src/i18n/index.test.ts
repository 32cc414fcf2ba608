import { afterAll, beforeEach, describe, expect, it, vi } from "vitest";
import { stubLocalStorage } from "../fixtures/localStorage";
import { currentLanguage, formatNumber, speak, startLanguage, switchLanguage, t, type Key } from "./index";
import { LANGUAGE_KEY } from "./languages";
import fr from "./locales/fr.json";

describe("the language shown", () => {
  beforeEach(() => {
    stubLocalStorage();
  });

  afterAll(async () => {
    await switchLanguage("en");
  });

  it("switches in place, fetching the catalogue, and keeps the choice", async () => {
    await switchLanguage("fr");
    expect(currentLanguage()).toBe("fr");
    expect(t("start.start")).toBe("Lancer une recherche");
    expect(localStorage.getItem(LANGUAGE_KEY)).toBe("fr");
    expect(formatNumber(1234.5)).toBe("1\u202f234,5");
  });

  it("starts in the kept choice over the phone's languages", async () => {
    localStorage.setItem(LANGUAGE_KEY, "ja");
    vi.stubGlobal("navigator", { languages: ["de-DE"], language: "de-DE" });
    await startLanguage();
    expect(t("tap.undo")).toBe("元に戻す");
    localStorage.removeItem(LANGUAGE_KEY);
    await startLanguage();
    expect(t("tap.undo")).toBe("Zurück");
  });

  it("remembers words per language and options, and forgets them on a switch", async () => {
    await switchLanguage("en");
    expect(t("step.findHere", { id: 3 })).toBe(t("step.findHere", { id: 3 }));
    const three = t("step.findHere", { id: 3 });
    expect(three).toContain("3");
    expect(t("step.findHere", { id: 4 })).toContain("4");
    expect(formatNumber(1234.5)).toBe("1,234.5");
    await switchLanguage("de");
    expect(t("step.findHere", { id: 3 })).not.toBe(three);
    expect(t("step.findHere", { id: 3 })).toContain("3");
    expect(formatNumber(1234.5)).toBe("1.234,5");
  });

  it("says a count in its language's plural form, else `_other`, else the plain key; a key it lacks as itself", async () => {
    await switchLanguage("en");
    expect(t("step.tapMore", { count: 1 })).toBe("Tap 1 more landmark");
    expect(t("step.tapMore", { count: 2 })).toBe("Tap 2 more landmarks");
    // French says a million in a form of its own ("many"), worded in its catalogue as "other"
    // is: made-up sentences tell the forms apart.
    const test = {
      count_one: "un",
      count_many: "{{count}} beaucoup",
      count_other: "{{count}} autres",
      lone_other: "{{count}} seuls",
      plain: "{{count}} tout court",
    };
    await speak("fr", { ...fr, test });
    const say = (key: string, count: number): string => t(key as Key, { count });
    expect([1, 1_000_000, 2].map((count) => say("test.count", count))).toEqual(["un", "1000000 beaucoup", "2 autres"]);
    expect(say("test.lone", 1)).toBe("1 seuls");
    expect(say("test.plain", 3)).toBe("3 tout court");
    expect(say("test.nowhere", 3)).toBe("test.nowhere");
    expect(t("start.start")).toBe("Lancer une recherche");
  });
});
