/**
 * What an event of the session's stream does to the state a phone shows. A change's event
 * carries what the other phone needs to show it (the server's `SessionEvents`, typed from
 * its OpenAPI schema): taken into the state of the version before it, it gives the state of
 * its own version, and nothing is fetched. A phone that finds a version missing (it was
 * away), or an event that cannot tell (a join code renewed: codes go in no event; taps
 * overtaken by another change), fetches the state instead: it never guesses.
 */

import type { EventData, Role, SessionState } from "./types";

/** An event of the stream: its type, and its data (JSON, as parsed). */
export interface Change {
  readonly type: string;
  readonly data: unknown;
}

/** What to do with a change: nothing (the state shows it already, as after the phone's own
 * PUT), show the new state, or fetch the state. */
export type Outcome =
  | { readonly kind: "shown" }
  | { readonly kind: "applied"; readonly state: SessionState }
  | { readonly kind: "fetch" };

const SHOWN: Outcome = { kind: "shown" };
const FETCH: Outcome = { kind: "fetch" };

/** The state `shown` with `change` taken in. */
export function takeIn(shown: SessionState | null, change: Change): Outcome {
  const data = change.data;
  if (!shown || typeof data !== "object" || data === null) return FETCH;
  const version = (data as { version?: unknown }).version;
  switch (change.type) {
    case "joined":
    case "left":
      return presence(shown, data as EventData["joined"]);
    case "answer":
      return typeof version === "number" ? answered(shown, data as EventData["answer"]) : FETCH;
    case "photo":
    case "taps":
      if (typeof version !== "number") return FETCH;
      if (version <= shown.version) return SHOWN;
      if (version > shown.version + 1) return FETCH;
      return change.type === "photo"
        ? photo(shown, data as EventData["photo"])
        : taps(shown, data as EventData["taps"]);
    default:
      // A renewed code (or anything newer than this app): shown if its version is.
      return typeof version === "number" && version <= shown.version ? SHOWN : FETCH;
  }
}

/** A new version: the answer of the one before goes (the hold in session.ts keeps it on
 * screen a moment while the new one is computed). */
function changed(shown: SessionState, version: number): SessionState {
  return { ...shown, version, answer: null, answer_version: null, answer_error: null };
}

function presence(shown: SessionState, data: EventData["joined"]): Outcome {
  const { role, online, version } = data;
  const before = shown.participants[role];
  if (!before) return FETCH;
  const participants = (joined: boolean) => ({ ...shown.participants, [role]: { joined, online } });
  if (version === null || version === undefined) {
    // A phone's stream opened or closed: no change of the session.
    return before.online === online ? SHOWN : { kind: "applied", state: { ...shown, participants: participants(before.joined) } };
  }
  // The joiner joined: the starter's code is used up.
  if (version <= shown.version) return SHOWN;
  if (version > shown.version + 1) return FETCH;
  const state = { ...changed(shown, version), participants: participants(true) };
  return { kind: "applied", state: { ...state, join_code: null, join_code_expires_at: null, join_url: null } };
}

function answered(shown: SessionState, data: EventData["answer"]): Outcome {
  if (data.version < shown.version) return SHOWN;
  if (data.version > shown.version) return FETCH;
  const known = (shown.answer ?? null) !== null || (shown.answer_error ?? null) !== null;
  if (known) return SHOWN;
  const error = data.answer_error?.[shown.you] ?? null;
  return {
    kind: "applied",
    state: {
      ...shown,
      answer: data.answer,
      answer_version: data.answer ? data.version : null,
      answer_error: error,
      landmarks_needed: data.landmarks_needed,
    },
  };
}

function photo(shown: SessionState, data: EventData["photo"]): Outcome {
  return {
    kind: "applied",
    state: {
      ...changed(shown, data.version),
      photos: withRole(shown.photos, data.role, data.photo),
      taps: withRole(shown.taps, data.role, null),
      landmarks_needed: data.landmarks_needed,
    },
  };
}

function taps(shown: SessionState, data: EventData["taps"]): Outcome {
  if (data.landmarks_needed === null) return FETCH; // overtaken: the count is the state's to say
  return {
    kind: "applied",
    state: {
      ...changed(shown, data.version),
      taps: withRole(shown.taps, data.role, data.taps),
      landmarks_needed: data.landmarks_needed,
    },
  };
}

function withRole<T>(map: { [role: string]: T }, role: Role, value: T): { [role: string]: T } {
  return { ...map, [role]: value };
}
