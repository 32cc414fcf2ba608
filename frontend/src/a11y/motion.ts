/**
 * Whether the person asked their phone for less motion (the system's "reduce motion"): the
 * photo view then jumps to the answer instead of gliding (panZoom.ts).
 */

export const REDUCE_MOTION_QUERY = "(prefers-reduced-motion: reduce)";

/** The system's choice now (`matchMedia`: another place to ask, for tests); false where the
 * page cannot ask (no matchMedia). */
export function prefersReducedMotion(matchMedia?: (query: string) => { matches: boolean }): boolean {
  if (matchMedia) return matchMedia(REDUCE_MOTION_QUERY).matches;
  // Asked once: the list's `matches` follows the setting, and a new list per render cost a
  // slowed phone's tap several ms.
  system ??= globalThis.matchMedia?.(REDUCE_MOTION_QUERY) ?? null;
  return system?.matches ?? false;
}

let system: { matches: boolean } | null = null;
