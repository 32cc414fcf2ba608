/**
 * The file inputs behind the big photo buttons (labels point at them): one opens the
 * camera, one the gallery. Always in the page while in a session.
 */

import { PHOTO_INPUTS, PICK_PHOTO, TAKE_PHOTO } from "../a11y/labels";
import type { SessionController } from "../session";

export function PhotoInputs({ controller }: { controller: SessionController }) {
  const chosen = (event: Event): void => {
    const input = event.currentTarget as HTMLInputElement;
    const file = input.files?.[0];
    input.value = ""; // the same photo can be chosen again
    if (file) void controller.photo.choose(file);
  };
  // A named region: every part of the page is in a landmark, these inputs too (axe's "region").
  return (
    <section aria-label={PHOTO_INPUTS}>
      <input
        id="photo-input"
        data-testid="photo-input"
        class="visually-hidden"
        type="file"
        accept="image/*"
        capture="environment"
        aria-label={TAKE_PHOTO}
        onChange={chosen}
      />
      <input id="photo-pick" class="visually-hidden" type="file" accept="image/*" aria-label={PICK_PHOTO} onChange={chosen} />
    </section>
  );
}
