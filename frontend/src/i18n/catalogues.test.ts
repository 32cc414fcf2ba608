/**
 * Every language says everything English says: the same keys, the same placeholders, the
 * plural forms its own rules need (Intl.PluralRules), and a sentence for every warning,
 * refusal and error code the server can send (read from the server's API types and its
 * error codes, so a new code fails here until each language has its words).
 */

import { describe, expect, it } from "vitest";
import de from "./locales/de.json";
import en from "./locales/en.json";
import es from "./locales/es.json";
import fr from "./locales/fr.json";
import ja from "./locales/ja.json";
import { LANGUAGES, type Language } from "./languages";
// The server's codes as it writes them (Vite's ?raw: the file's text).
import serviceErrors from "../../../backend/errors.py?raw";
import apiTypes from "../generated/openapi.ts?raw";

const CATALOGUES: Record<Language, unknown> = { en, es, fr, de, ja };
const PLURAL = /_(zero|one|two|few|many|other)$/;

/** The catalogue flattened: "section.key" -> sentence. */
function flat(tree: unknown, prefix = ""): Map<string, string> {
  const out = new Map<string, string>();
  for (const [key, value] of Object.entries(tree as Record<string, unknown>)) {
    const path = prefix ? `${prefix}.${key}` : key;
    if (typeof value === "string") out.set(path, value);
    else for (const [k, v] of flat(value, path)) out.set(k, v);
  }
  return out;
}

/** The keys as the code asks for them: plural forms under their base key. */
function bases(words: Map<string, string>): Map<string, string[]> {
  const out = new Map<string, string[]>();
  for (const key of words.keys()) {
    const match = PLURAL.exec(key);
    const base = match ? key.slice(0, match.index) : key;
    out.set(base, [...(out.get(base) ?? []), ...(match?.[1] ? [match[1]] : [])]);
  }
  return out;
}

/** A sentence's placeholders, by name ({{Photo1}} is photo1 at a sentence's start: a
 * language may start its sentence elsewhere), and any format they ask for. */
function placeholders(text: string): string[] {
  return [...new Set([...text.matchAll(/\{\{\s*([^}]+?)\s*\}\}/g)].map((m) => (m[1] ?? "").toLowerCase()))].sort();
}

/** The string literals of a TypeScript union in the generated API types. */
function union(name: string): string[] {
  const line = new RegExp(`^\\s*${name}: ((?:"[^"]+"(?: \\| )?)+);`, "m").exec(apiTypes);
  if (!line?.[1]) throw new Error(`no ${name} in the API types`);
  return [...line[1].matchAll(/"([^"]+)"/g)].map((m) => m[1] ?? "");
}

/** The service's refusal codes (backend/errors.py, ErrorCode): not all are in the API types. */
function serviceCodes(): string[] {
  const body = /class ErrorCode\(StrEnum\):([\s\S]*?)\n\n\S/.exec(serviceErrors)?.[1] ?? "";
  return [...body.matchAll(/^\s+[A-Z_]+ = "([a-z_]+)"$/gm)].map((m) => m[1] ?? "");
}

/**
 * Reasons only a script calling the solver can be refused for (malformed values, the
 * drawing's input): a phone's taps never make them, so no phone needs their words. A new
 * reason must be put here or in the catalogues.
 */
const SCRIPT_ONLY = new Set([
  "not_a_number", "not_points", "not_a_point", "not_a_pixel", "not_a_line", "not_a_direction",
  "not_a_size", "not_precisions", "not_a_precision", "not_8_bit", "not_a_photo", "labels_not_whole",
  "not_finite", "beyond_floats", "one_id_per_landmark", "labels_without_points",
  "one_label_per_landmark", "too_far", "not_positive", "not_a_length", "not_an_angle",
  "not_a_covariance", "not_a_usable_covariance", "not_a_camera", "camera_without_size",
  "five_method", "bad_photo", "missing_epipole1",
]);

const english = flat(en);
const englishBases = bases(english);

describe("the catalogues", () => {
  for (const language of Object.keys(LANGUAGES) as Language[]) {
    const words = flat(CATALOGUES[language]);
    const keys = bases(words);

    it(`${language}: has every key English has, and no other`, () => {
      expect([...keys.keys()].sort()).toEqual([...englishBases.keys()].sort());
    });

    it(`${language}: has the plural forms its language needs, and only those`, () => {
      const needed = [...new Intl.PluralRules(language).resolvedOptions().pluralCategories].sort();
      for (const [base, forms] of englishBases) {
        if (forms.length === 0) continue;
        expect({ base, forms: [...(keys.get(base) ?? [])].sort() }).toEqual({ base, forms: needed });
      }
    });

    it(`${language}: names the same placeholders as English in each sentence`, () => {
      for (const [key, text] of words) {
        expect(text.trim(), key).not.toBe("");
        const base = key.replace(PLURAL, "");
        const model = english.get(key) ?? english.get(`${base}_other`) ?? "";
        // {{count}} may go unsaid where the plural form says it ("one person").
        const wanted = placeholders(model).filter((name) => !(PLURAL.test(key) && name === "count"));
        const said = placeholders(text).filter((name) => !(PLURAL.test(key) && name === "count"));
        expect({ key, said }).toEqual({ key, said: wanted });
      }
    });
  }

  const refusals = (): string[] => union("Reason").filter((reason) => !SCRIPT_ONLY.has(reason));
  const errors = (): string[] => [...serviceCodes(), ...union("ErrorCode")];
  it.each([
    ["words every warning code the server sends", "warning", () => union("WarningCode"), 0],
    ["words every refusal a phone can be told, by its reason", "refusal", refusals, 0],
    ["words every error code of the service and of the solver", "error", errors, 40],
  ] as const)("%s", (_, section, codes, least) => {
    expect(codes().length).toBeGreaterThan(least);
    for (const code of codes()) expect(englishBases.has(`${section}.${code}`), code).toBe(true);
  });
});
