/**
 * The app's words: one catalogue per language (locales/*.json), each its own chunk, so a
 * phone fetches only the language it speaks before the first render. rosetta (300 bytes)
 * holds the catalogues and fills a sentence's `{{name}}`s; Intl does the rest: a count picks
 * its plural form (i18next's JSON v4 suffixes, `_one`/`_many`/`_other`) by
 * `Intl.PluralRules`, and numbers are written by `Intl.NumberFormat` in the language shown
 * (`formatNumber`). Not i18next: it was 16 kB gzipped of the 70 kB the start and tap screens
 * may load (docs/slow-phone.md), and its plural rules and number formats came from Intl
 * anyway. Keys are typed from the English catalogue: a missing or misspelt key fails `tsc`.
 */

import rosetta from "rosetta";
import { useEffect, useState } from "preact/hooks";
import type en from "./locales/en.json";
import { DEFAULT_LANGUAGE, LANGUAGE_KEY, chooseLanguage, isLanguage, type Language } from "./languages";

export type Catalogue = typeof en;

/** A catalogue's nested keys, dot-joined ("start.start"). */
type Paths<T> = { [K in keyof T & string]: T[K] extends string ? K : `${K}.${Paths<T[K]>}` }[keyof T & string];

/** A plural's forms under the one key the code asks for (`t("step.tapMore", { count })`). */
type Singular<K> = K extends `${infer Base}_one` | `${infer Base}_many` | `${infer Base}_other` ? Base : K;

/** Every key `t` takes: the English catalogue's, its plurals by their base. */
export type Key = Singular<Paths<Catalogue>>;

/** A sentence's `{{name}}`s; a numeric `count` also picks its plural form. */
export type Params = Readonly<Record<string, string | number>>;

/** One loader per language: Vite makes each catalogue a chunk of its own. */
const CATALOGUES: Record<Language, () => Promise<{ default: unknown }>> = {
  en: () => import("./locales/en.json"),
  es: () => import("./locales/es.json"),
  fr: () => import("./locales/fr.json"),
  de: () => import("./locales/de.json"),
  ja: () => import("./locales/ja.json"),
};

const i18n = rosetta<Record<string, unknown>>();

/**
 * Values made once per id: at most `most` kept, all forgotten beyond it (counts and
 * distances make new ids without end).
 */
function memo<T>(most: number): { get(id: string, make: () => T): T; clear(): void } {
  const kept = new Map<string, T>();
  return {
    get(id, make) {
      let value = kept.get(id);
      if (value === undefined) {
        if (kept.size >= most) kept.clear();
        value = make();
        kept.set(id, value);
      }
      return value;
    },
    clear: () => kept.clear(),
  };
}

/**
 * Sentences by language, key and parameters. A tap re-renders screens that ask for a hundred
 * words; resolving each afresh was a fifth of a tap's time on a phone slowed 4x
 * (docs/slow-phone.md). Forgotten when a catalogue is given.
 */
const WORDS = memo<string>(4000);
// Made once per language (and options): a new Intl object costs far more than using one.
const FORMATS = memo<Intl.NumberFormat>(100);
const PLURALS = memo<Intl.PluralRules>(10);

/** A word or sentence in the language shown; a key the catalogue lacks shows as itself. */
export function t(key: Key, params?: Params): string {
  const language = currentLanguage();
  const id = params ? `${language}\u0000${key}\u0000${JSON.stringify(params)}` : `${language}\u0000${key}`;
  return WORDS.get(id, () => {
    const count = params?.count;
    const forms =
      typeof count === "number"
        ? [`${key}_${PLURALS.get(language, () => new Intl.PluralRules(language)).select(count)}`, `${key}_other`]
        : [];
    const found = [...forms, key].find(exists);
    return found === undefined ? key : i18n.t(found, params, language);
  });
}

/**
 * The sentence `key` names in the language shown as the catalogue writes it, `{{name}}`s and
 * all; undefined when the catalogue has none (keys made from a server's code are open-ended).
 */
export function template(key: string): string | undefined {
  let node: unknown = i18n.table(currentLanguage());
  for (const part of key.split(".")) node = (node as Record<string, unknown> | undefined)?.[part];
  return typeof node === "string" ? node : undefined;
}

/** Whether the language shown has a sentence for `key` (a plural's only under its forms). */
export function exists(key: string): boolean {
  return template(key) !== undefined;
}

/** The language shown now. */
export function currentLanguage(): Language {
  const language = i18n.locale();
  return isLanguage(language) ? language : DEFAULT_LANGUAGE;
}

/** Who re-renders when the language changes (`useLanguage`). */
const LISTENERS = new Set<(language: Language) => void>();

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

/** Show `language`, with `words` as its catalogue when given. */
function show(language: Language, words: Record<string, unknown> | null): void {
  if (words) i18n.set(language, words);
  WORDS.clear();
  i18n.locale(language);
  if (typeof document !== "undefined") document.documentElement.lang = language;
  for (const listener of LISTENERS) listener(language);
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
  show(language, words);
}

/** The switch: fetch the language's catalogue, speak it, and remember the choice. */
export async function switchLanguage(language: Language): Promise<void> {
  show(language, i18n.table(language) ? null : await catalogue(language));
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
    LISTENERS.add(setLanguage);
    return () => {
      LISTENERS.delete(setLanguage);
    };
  }, []);
  return language;
}

/** A number as the language shown writes it ("1,234.5", "1.234,5", "1 234,5"). */
export function formatNumber(value: number, options?: Intl.NumberFormatOptions): string {
  const language = currentLanguage();
  const id = `${language} ${JSON.stringify(options ?? {})}`;
  return FORMATS.get(id, () => new Intl.NumberFormat(language, options)).format(value);
}
