/**
 * The server's sentences a phone shows, from the catalogue by code (never by the English
 * sentence): a warning by its `code` and parameters, a refusal of the answer by its `reason`
 * and parameters, a refused request by its error `code`. The server's own sentence is kept
 * for a code this app does not know yet (a newer server), so nothing is ever left unsaid.
 */

import { ApiError } from "../api";
import type { Refusal, SolverWarning as Warning } from "../types";
import { exists, formatNumber, t, template, type Key, type Params } from "./index";

/** `t` for a key made from a server's code, checked with `exists` first (or by its plural's forms). */
function say(key: string, params: Params): string {
  return t(key as Key, params);
}

/** A distance in px as the language writes it, whole. */
function px(value: number | null | undefined): string {
  return formatNumber(value ?? 0, { maximumFractionDigits: 0 });
}

/** A warning's sentence in the language shown. */
export function warningText(warning: Warning): string {
  const key = `warning.${warning.code}`;
  if (!exists(key)) return warning.message;
  const side = warning.side ?? "left";
  return say(key, {
    landmark: warning.landmark ?? "",
    distance: px(warning.distance_px),
    edge: say(`warning.edge_${side}`, {}),
    turn: say(`warning.turn_${side}`, {}),
    decide: say(`warning.decide_${warning.marked ?? "none"}`, {}),
  });
}

/**
 * A refusal of the answer in the language shown. Its `reader` says which of the solver's
 * photos is this phone's ("your photo"); a sentence that names a photo needs it, so without
 * one (an older server) the server's own sentence is shown.
 */
export function refusalText(refusal: Refusal): string {
  const yours = refusal.reader ?? null;
  const key = `refusal.${refusal.reason}`;
  // A sentence with a count is kept by its plural forms only (`_one`, `_other`...).
  const sentence = template(key) ?? template(`${key}_other`);
  if (sentence === undefined) return refusal.message;
  const namesPhoto = /\{\{(photo|photo1|photo2|Photo1)\}\}/.test(sentence);
  if (namesPhoto && yours === null) return refusal.message;
  const name = (number: 1 | 2, capital: boolean): string =>
    say(number === yours ? (capital ? "refusal.YourPhoto" : "refusal.yourPhoto") : capital ? "refusal.FriendsPhoto" : "refusal.friendsPhoto", {});
  const [first, second] = refusal.counts ?? refusal.landmarks ?? [0, 0];
  return say(key, {
    count: refusal.count ?? 0,
    minimum: refusal.minimum ?? "",
    maximum: refusal.maximum ?? "",
    landmark: refusal.landmark ?? "",
    first,
    second,
    purpose: say(`refusal.purpose_${refusal.marked ?? "here"}`, {}),
    photo: refusal.photo ? name(refusal.photo, false) : "",
    photo1: name(1, false),
    photo2: name(2, false),
    Photo1: name(1, true),
  });
}

/**
 * A label the server drew on the photo, in the language shown. The drawing names its frame
 * with a word, not a code ("friend", or "friend?" without a sure region): these two are the
 * frames' only labels (shared_solver/words.py, DRAWN_FRIEND*); any other is shown as sent.
 */
export function drawnLabel(label: string): string {
  if (label === "friend") return t("answer.drawnFriend");
  if (label === "friend?") return t("answer.drawnFriendLikely");
  return label;
}

/**
 * What a failed request says: the catalogue's sentence for its error code (the server's
 * codes, and the app's own: `network`, `bad_answer`, `http_NNN` for an answer without one),
 * else the server's sentence.
 */
export function errorText(error: unknown): string {
  if (!(error instanceof ApiError)) return error instanceof Error ? error.message : String(error);
  if (error.code.startsWith("http_")) {
    return error.status >= 500 ? t("error.server") : t("error.refused", { status: error.status });
  }
  const key = `error.${error.code}`;
  return exists(key) ? say(key, {}) : error.message;
}
