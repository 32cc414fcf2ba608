/**
 * What survives a reload: the session this phone is in (id, token, role), taps not yet on
 * the server, and the server's last state this phone saw (shown after a reload with no
 * signal). Kept in localStorage; a phone without it (private mode) still works until the
 * page is closed.
 */

import { isRole, type Credentials, type SessionState, type Taps } from "./types";

const SESSION_KEY = "buddy-search.session";
const DRAFT_KEY = "buddy-search.draft";
const KEPT_STATE_KEY = "buddy-search.state";

function read<T>(key: string): T | null {
  try {
    const text = localStorage.getItem(key);
    return text ? (JSON.parse(text) as T) : null;
  } catch {
    return null;
  }
}

function write(key: string, value: unknown): void {
  try {
    if (value === null) localStorage.removeItem(key);
    else localStorage.setItem(key, JSON.stringify(value));
  } catch {
    // storage full or disabled: the session lasts until the page closes
  }
}

export function loadCredentials(): Credentials | null {
  const stored = read<Partial<Credentials>>(SESSION_KEY);
  if (
    stored &&
    typeof stored.session_id === "string" &&
    typeof stored.token === "string" &&
    isRole(stored.role)
  ) {
    return { session_id: stored.session_id, token: stored.token, role: stored.role };
  }
  return null;
}

export function saveCredentials(credentials: Credentials): void {
  write(SESSION_KEY, credentials);
  write(DRAFT_KEY, null);
  write(KEPT_STATE_KEY, null);
}

export function forgetSession(): void {
  write(SESSION_KEY, null);
  write(DRAFT_KEY, null);
  write(KEPT_STATE_KEY, null);
}

/**
 * The server's latest state of the session, kept on the phone: after a reload with no
 * signal the session screen shows it (and the draft's taps over it) instead of an error.
 * It holds nothing the phone did not already have (its token is kept beside it).
 */
export function keepState(sessionId: string, state: SessionState): void {
  write(KEPT_STATE_KEY, { session_id: sessionId, state });
}

export function loadKeptState(sessionId: string): SessionState | null {
  const kept = read<{ session_id?: unknown; state?: SessionState }>(KEPT_STATE_KEY);
  const state = kept?.session_id === sessionId ? kept.state : undefined;
  return state && typeof state.version === "number" ? state : null;
}

/**
 * Taps of this phone that the server may not have yet, landmarks it skipped, and whether
 * it said it cannot see the friend.
 */
export interface Draft {
  session_id: string;
  taps: Taps | null;
  unsaved: boolean;
  skipped: number[];
  unseen?: boolean;
}

export function loadDraft(sessionId: string): Draft | null {
  const draft = read<Draft>(DRAFT_KEY);
  return draft && draft.session_id === sessionId ? draft : null;
}

export function saveDraft(draft: Draft): void {
  write(DRAFT_KEY, draft);
}

const SHUTTER_KEY = "buddy-search.shutter";
/** This page's load: a relative orientation's reference is the sensor's while the page
 * runs, and may not be the same after a reload. */
const PAGE = `${Date.now()}-${Math.random().toString(36).slice(2)}`;

/**
 * The phone's orientation at the in-app camera's shutter for its current photo (live/:
 * the anchor, the photo's camera frame into the orientation sensor's reference frame, row by
 * row), with the page it was read on. Only the phone keeps it.
 */
interface ShutterRecord {
  session_id: string;
  page: string;
  anchor: number[][];
}

/** A new photo: its anchor, or null (a gallery photo, a moving phone, no sensor). */
export function saveShutterAnchor(sessionId: string, anchor: readonly (readonly number[])[] | null): void {
  write(SHUTTER_KEY, anchor ? { session_id: sessionId, page: PAGE, anchor: anchor.map((row) => [...row]) } : null);
}

/**
 * The anchor of this session's photo, if it was read on this very page: after a reload the
 * sensor's reference may have moved, and "Show me" aligns on a frame instead.
 */
export function loadShutterAnchor(sessionId: string): number[][] | null {
  const stored = read<Partial<ShutterRecord>>(SHUTTER_KEY);
  if (!stored || stored.session_id !== sessionId || stored.page !== PAGE) return null;
  const anchor = stored.anchor;
  const valid = Array.isArray(anchor) && anchor.length === 3 && anchor.every((row) => Array.isArray(row) && row.length === 3 && row.every(Number.isFinite));
  return valid ? anchor : null;
}
