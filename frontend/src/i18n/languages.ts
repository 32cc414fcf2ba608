/**
 * The languages the app speaks, and which one a phone gets: the one the person chose with the
 * switch (kept in localStorage), else the first of the phone's languages (`navigator.languages`)
 * the app has, else English. Pure, so the choice is tested without a browser.
 */

/** Each language by its code, named in itself: a person looks for their own language's name. */
export const LANGUAGES = {
  en: "English",
  es: "Español",
  fr: "Français",
  de: "Deutsch",
  ja: "日本語",
} as const;

export type Language = keyof typeof LANGUAGES;

export const DEFAULT_LANGUAGE: Language = "en";

/** Where the switch's choice is kept (a key of its own: leaving a search keeps it). */
export const LANGUAGE_KEY = "buddy-search.language";

export function isLanguage(value: unknown): value is Language {
  return typeof value === "string" && Object.hasOwn(LANGUAGES, value);
}

/**
 * The language to speak: `chosen` (the switch's, when it names one of ours), else the first of
 * `preferred` (BCP 47 tags, the phone's order: "de-AT" is German) the app has, else English.
 */
export function chooseLanguage(preferred: readonly string[], chosen: string | null): Language {
  if (isLanguage(chosen)) return chosen;
  for (const tag of preferred) {
    const base = tag.toLowerCase().split("-")[0];
    if (isLanguage(base)) return base;
  }
  return DEFAULT_LANGUAGE;
}
