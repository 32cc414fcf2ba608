/**
 * Whether a reload now would lose something: the app's parts say what only this page holds
 * (a photo the server does not have yet), and a new build waits for them (update.ts).
 * Taps need no say: unsaved ones are in localStorage and go after a reload (storage.ts).
 */

const checks = new Set<() => boolean>();

/** `holds()` says whether this page holds something a reload would lose; returns the undo. */
export function holdsUnsent(holds: () => boolean): () => void {
  checks.add(holds);
  return () => checks.delete(holds);
}

export function pageHoldsUnsent(): boolean {
  for (const holds of checks) if (holds()) return true;
  return false;
}
