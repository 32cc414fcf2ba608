/**
 * The colours of the app's marks, read from the server's own palette
 * (shared_solver/drawing/palette.json, which its drawings read too), so "the orange 3" is the
 * same spot on both phones and in the answer's overlay. The stylesheet gets them as CSS
 * custom properties set here (styles.css holds no copy).
 */

import palette from "../../shared_solver/drawing/palette.json";

/** Landmark k is painted LANDMARK_COLOURS[(k - 1) % 12]. */
export const LANDMARK_COLOURS: readonly string[] = palette.landmarks.map((colour) => colour.hex);
/** The friend: star, ring, arrow, curve, the friend mark and line. */
export const FRIEND_COLOUR: string = palette.friend;
/** A landmark to re-check. */
export const SUSPECT_COLOUR: string = palette.suspect;
/** Under every stroke and letter, so colours read on bright photos too. */
export const OUTLINE_COLOUR: string = palette.outline;
/** How much of the friend's colour a curve's band (the level from gravity) lays over the photo. */
export const BAND_OPACITY: number = palette.band_opacity;

/** The colour of landmark number `id` (from 1; the table repeats every 12). */
export function landmarkColour(id: number): string {
  const count = LANDMARK_COLOURS.length;
  const index = (((id - 1) % count) + count) % count;
  return LANDMARK_COLOURS[index] ?? FRIEND_COLOUR;
}

/**
 * The CSS custom properties the stylesheet paints with. A landmark's colour is set on its
 * own element (`--c`, from {@link landmarkColour}).
 */
export function paletteProperties(): Record<string, string> {
  return { "--friend": FRIEND_COLOUR, "--suspect": SUSPECT_COLOUR, "--outline": OUTLINE_COLOUR };
}

/**
 * Set the palette's properties on `style` (the page's root): through the CSSOM, which the
 * page's Content-Security-Policy allows where an inline <style> would not be.
 */
export function applyPalette(style: Pick<CSSStyleDeclaration, "setProperty">): void {
  for (const [name, value] of Object.entries(paletteProperties())) style.setProperty(name, value);
}
