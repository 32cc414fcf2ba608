import { afterAll, describe, expect, it, vi } from "vitest";
import { stubLocalStorage } from "../fixtures/localStorage";
import { currentLanguage, formatNumber, startLanguage, switchLanguage, t } from "./index";
import { LANGUAGE_KEY } from "./languages";

describe("the language shown", () => {
  afterAll(async () => {
    await switchLanguage("en");
  });

  it("switches in place, fetching the catalogue, and keeps the choice", async () => {
    stubLocalStorage();
    await switchLanguage("fr");
    expect(currentLanguage()).toBe("fr");
    expect(t("start.start")).toBe("Lancer une recherche");
    expect(localStorage.getItem(LANGUAGE_KEY)).toBe("fr");
    expect(formatNumber(1234.5)).toBe("1\u202f234,5");
  });

  it("starts in the kept choice over the phone's languages", async () => {
    stubLocalStorage();
    localStorage.setItem(LANGUAGE_KEY, "ja");
    vi.stubGlobal("navigator", { languages: ["de-DE"], language: "de-DE" });
    await startLanguage();
    expect(t("tap.undo")).toBe("元に戻す");
    localStorage.removeItem(LANGUAGE_KEY);
    await startLanguage();
    expect(t("tap.undo")).toBe("Zurück");
  });

  it("remembers words per language and options, and forgets them on a switch", async () => {
    stubLocalStorage();
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
});
