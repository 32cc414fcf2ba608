/**
 * The contrast of the words drawn over the photo, where axe can only say "needs review"
 * (testbed/browser/audit.py): checked here against the palette (shared_solver/drawing/palette.json,
 * the one source of the marks' colours) and the stylesheet's scrim behind the status.
 */

import { describe, expect, it } from "vitest";
import css from "../styles.css?raw";
import { FRIEND_COLOUR, LANDMARK_COLOURS, OUTLINE_COLOUR, SUSPECT_COLOUR } from "../palette";
import { AA_TEXT, contrast, over, parseHex, type Rgb } from "./contrast";

const BLACK: Rgb = [0, 0, 0];
const WHITE: Rgb = [255, 255, 255];

/** A custom property's #rrggbb value in the stylesheet's :root. */
function property(name: string): Rgb {
  const m = new RegExp(`${name}:\\s*(#[0-9a-f]{6})`, "i").exec(css);
  if (!m) throw new Error(`${name} not in styles.css`);
  return parseHex(m[1] as string);
}

/** The status's scrim, black at some opacity: the last `.status { background: ... }` rule
 * (the a11y block's, which overrides the layout's). */
function scrim(): number {
  const rule = /\n\.status \{[^}]*background: rgba?\(0,? 0,? 0(?:, | \/ )([\d.]+)(%?)\)/g;
  const last = [...css.matchAll(rule)].at(-1);
  if (!last) throw new Error("no .status scrim in styles.css");
  return Number(last[1]) / (last[2] ? 100 : 1);
}

describe("contrast over the photo", () => {
  it("computes WCAG's ratio", () => {
    expect(contrast(BLACK, WHITE)).toBeCloseTo(21);
    expect(contrast(parseHex("#767676"), WHITE)).toBeCloseTo(4.54, 2);
  });

  it("a landmark's number (black) reads on every landmark colour and the suspect's", () => {
    for (const colour of [...LANDMARK_COLOURS, SUSPECT_COLOUR, FRIEND_COLOUR]) {
      expect(contrast(BLACK, parseHex(colour)), colour).toBeGreaterThanOrEqual(AA_TEXT);
    }
  });

  it("the answer's yellow words read on their dark outline", () => {
    expect(contrast(parseHex(FRIEND_COLOUR), parseHex(OUTLINE_COLOUR))).toBeGreaterThanOrEqual(AA_TEXT);
  });

  it("the status's words read on its scrim over a white photo", () => {
    const worst = over(BLACK, scrim(), WHITE);
    const words = {
      text: WHITE,
      answer: parseHex(FRIEND_COLOUR),
      muted: property("--muted"),
      seen: property("--green"),
      poor: property("--warning"),
    };
    for (const [name, colour] of Object.entries(words)) {
      expect(contrast(colour, worst), name).toBeGreaterThanOrEqual(AA_TEXT);
    }
  });
});
