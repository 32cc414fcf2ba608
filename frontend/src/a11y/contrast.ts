/**
 * WCAG 2 contrast, for the colours axe cannot judge: words over the photo (a landmark's
 * number on its colour, the status over the photo's top), whose background is the photo's
 * pixels. The worst photo is assumed instead: white under a dark scrim, or the scrim over
 * black. Definitions: WCAG 2.2, "relative luminance" and "contrast ratio".
 */

export type Rgb = readonly [number, number, number];

/** "#rrggbb" as 0..255 channels. */
export function parseHex(hex: string): Rgb {
  const m = /^#([0-9a-f]{2})([0-9a-f]{2})([0-9a-f]{2})$/i.exec(hex);
  if (!m) throw new Error(`not a #rrggbb colour: ${hex}`);
  return [parseInt(m[1] as string, 16), parseInt(m[2] as string, 16), parseInt(m[3] as string, 16)];
}

function linear(channel: number): number {
  const c = channel / 255;
  return c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4;
}

export function luminance([r, g, b]: Rgb): number {
  return 0.2126 * linear(r) + 0.7152 * linear(g) + 0.0722 * linear(b);
}

/** The contrast ratio of two colours, 1 to 21. */
export function contrast(a: Rgb, b: Rgb): number {
  const [hi, lo] = [luminance(a), luminance(b)].sort((x, y) => y - x) as [number, number];
  return (hi + 0.05) / (lo + 0.05);
}

/** `top` at `alpha` over `under`. */
export function over(top: Rgb, alpha: number, under: Rgb): Rgb {
  const mix = (i: 0 | 1 | 2): number => alpha * top[i] + (1 - alpha) * under[i];
  return [mix(0), mix(1), mix(2)];
}

/** WCAG's AA minimum for text under 24 px (18.66 px bold). */
export const AA_TEXT = 4.5;
