/**
 * What survives a reload: the session this phone is in (id, token, role), and taps not yet
 * on the server. Kept in localStorage; a phone without it (private mode) still works until
 * the page is closed.
 */

import { isRole, type Credentials, type Taps } from "./types";

const SESSION_KEY = "buddy-search.session";
const DRAFT_KEY = "buddy-search.draft";

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
}

export function forgetSession(): void {
  write(SESSION_KEY, null);
  write(DRAFT_KEY, null);
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
