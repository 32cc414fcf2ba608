/**
 * Focus follows the next step: when the screen changes under the person (the photo step
 * opens, their photo is shown, an answer arrives), focus moves to what to read or do next,
 * so a screen reader says it at once and a keyboard starts there. Smaller changes (the next
 * landmark to tap, a new mark) are announced by live regions instead: moving focus on every
 * tap would pull a screen reader away from the photo.
 */

import { useEffect } from "preact/hooks";

/**
 * Focus the element `target` gives whenever `key` changes to a value other than null (not on
 * other renders). Without scrolling: the screens are laid out to fit, and a scroll would
 * move the photo under a finger.
 */
export function useFocusOnChange(target: () => HTMLElement | null | undefined, key: string | null): void {
  useEffect(() => {
    if (key !== null) target()?.focus({ preventScroll: true });
  }, [key]);
}

/** The key of an answer worth moving focus to: a new kind of answer, or a new way it was
 * found (not every refinement: those the status announces); null before an answer. */
export function answerFocusKey(kind: string, how: string | null): string | null {
  return kind === "none" ? null : `${kind}:${how ?? ""}`;
}
