/**
 * Whether the person asked their phone for less motion (the system's "reduce motion"): the
 * photo view then jumps to the answer instead of gliding (panZoom.ts).
 */

export const REDUCE_MOTION_QUERY = "(prefers-reduced-motion: reduce)";

/** The system's choice now; false where the page cannot ask (no matchMedia). */
export function prefersReducedMotion(
  matchMedia: ((query: string) => { matches: boolean }) | undefined = globalThis.matchMedia?.bind(globalThis),
): boolean {
  return matchMedia ? matchMedia(REDUCE_MOTION_QUERY).matches : false;
}
