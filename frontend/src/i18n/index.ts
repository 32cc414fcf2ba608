/**
 * The app's words: i18next with one catalogue per language (locales/*.json), each its own
 * chunk, so a phone fetches only the language it speaks before the first render. Keys are
 * typed from the English catalogue (a missing or misspelt key fails `tsc`); plurals use
 * i18next's `_one`/`_other` suffixes, chosen by `Intl.PluralRules`; numbers are formatted by
 * `Intl.NumberFormat` in the language shown (`{{n, number}}` in a catalogue, or `formatNumber`).
 */

import i18next from "i18next";
import { useEffect, useState } from "preact/hooks";
import type en from "./locales/en.json";
import { DEFAULT_LANGUAGE, LANGUAGE_KEY, chooseLanguage, isLanguage, type Language } from "./languages";

declare module "i18next" {
  interface CustomTypeOptions {
    resources: { translation: typeof en };
  }
}

export type Catalogue = typeof en;

/** One loader per language: Vite makes each catalogue a chunk of its own. */
const CATALOGUES: Record<Language, () => Promise<{ default: unknown }>> = {
  en: () => import("./locales/en.json"),
  es: () => import("./locales/es.json"),
  fr: () => import("./locales/fr.json"),
  de: () => import("./locales/de.json"),
  ja: () => import("./locales/ja.json"),
};

/**
 * A word or sentence in the language shown: i18next's `t`, remembered per language, key and
 * options. i18next resolves a key afresh on every call (its path, plural rule and
 * interpolation), and a tap re-renders screens that ask for a hundred words: on a phone
 * slowed 4x that was a fifth of a tap's time (docs/slow-phone.md). Forgotten when the
 * language or a catalogue changes.
 */
export const t = ((key: unknown, options?: unknown): string => {
  const id = remembered(key, options);
  if (id === null) return (i18next.t as (k: unknown, o?: unknown) => string)(key, options);
  let words = WORDS.get(id);
  if (words === undefined) {
    if (WORDS.size >= MOST_WORDS) WORDS.clear();
    words = (i18next.t as (k: unknown, o?: unknown) => string)(key, options);
    WORDS.set(id, words);
  }
  return words;
}) as typeof i18next.t;

const WORDS = new Map<string, string>();
const MOST_WORDS = 4000; // a bound: counts and distances make new options without end

/** The memo's key for a call; null for options the memo cannot tell apart (objects). */
function remembered(key: unknown, options: unknown): string | null {
  if (typeof key !== "string") return null;
  if (options === undefined) return `${i18next.language}\u0000${key}`;
  if (typeof options !== "object" || options === null) return null;
  for (const value of Object.values(options)) {
    if (value !== null && typeof value === "object") return null;
  }
  return `${i18next.language}\u0000${key}\u0000${JSON.stringify(options)}`;
}

i18next.on("languageChanged", () => WORDS.clear());

/** The language shown now. */
export function currentLanguage(): Language {
  const language = i18next.language;
  return isLanguage(language) ? language : DEFAULT_LANGUAGE;
}

function storedChoice(): string | null {
  try {
    return localStorage.getItem(LANGUAGE_KEY);
  } catch {
    return null; // storage blocked: the phone's language, every time
  }
}

async function catalogue(language: Language): Promise<Record<string, unknown>> {
  return (await CATALOGUES[language]()).default as Record<string, unknown>;
}

function markPage(language: Language): void {
  if (typeof document !== "undefined") document.documentElement.lang = language;
}

/** Start in the phone's language (or the one the person chose): before the first render. */
export async function startLanguage(): Promise<void> {
  const preferred = typeof navigator !== "undefined" ? (navigator.languages ?? [navigator.language]) : [];
  const language = chooseLanguage(preferred, storedChoice());
  await speak(language, await catalogue(language));
}

/**
 * Speak `language` with `words` (synchronous once the catalogue is at hand; the tests give the
 * English one directly). Missing keys show the key, never another language: the catalogue
 * test keeps every language complete.
 */
export async function speak(language: Language, words: Record<string, unknown>): Promise<void> {
  if (!i18next.isInitialized) {
    await i18next.init({
      lng: language,
      resources: { [language]: { translation: words } },
      fallbackLng: false,
      initAsync: false,
      // Preact escapes what it renders; escaping here would show "&amp;".
      interpolation: { escapeValue: false },
      returnNull: false,
    });
  } else {
    i18next.addResourceBundle(language, "translation", words, true, true);
    WORDS.clear();
    await i18next.changeLanguage(language);
  }
  markPage(language);
}

/** The switch: fetch the language's catalogue, speak it, and remember the choice. */
export async function switchLanguage(language: Language): Promise<void> {
  const words = i18next.hasResourceBundle(language, "translation") ? null : await catalogue(language);
  if (words) i18next.addResourceBundle(language, "translation", words, true, true);
  WORDS.clear();
  await i18next.changeLanguage(language);
  markPage(language);
  try {
    localStorage.setItem(LANGUAGE_KEY, language);
  } catch {
    // not kept: the switch still works for this page
  }
}

/** The language shown, re-rendering the caller's component when the switch changes it. */
export function useLanguage(): Language {
  const [language, setLanguage] = useState(currentLanguage);
  useEffect(() => {
    const changed = (): void => setLanguage(currentLanguage());
    i18next.on("languageChanged", changed);
    return () => i18next.off("languageChanged", changed);
  }, []);
  return language;
}

/** A number as the language shown writes it ("1,234.5", "1.234,5", "1 234,5"). */
export function formatNumber(value: number, options?: Intl.NumberFormatOptions): string {
  const id = `${currentLanguage()} ${JSON.stringify(options ?? {})}`;
  let format = FORMATS.get(id);
  if (!format) {
    format = new Intl.NumberFormat(currentLanguage(), options);
    FORMATS.set(id, format);
  }
  return format.format(value);
}

// Made once per language and options: a new Intl.NumberFormat costs far more than a format.
const FORMATS = new Map<string, Intl.NumberFormat>();
