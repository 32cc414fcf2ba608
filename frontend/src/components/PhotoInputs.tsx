/**
 * The file inputs behind the big photo buttons (labels point at them): one opens the
 * camera, one the gallery. Always in the page while in a session.
 */

import type { SessionController } from "../session";

export function PhotoInputs({ controller }: { controller: SessionController }) {
  const chosen = (event: Event): void => {
    const input = event.currentTarget as HTMLInputElement;
    const file = input.files?.[0];
    input.value = ""; // the same photo can be chosen again
    if (file) void controller.photo.choose(file);
  };
  return (
    <>
      <input
        id="photo-input"
        data-testid="photo-input"
        class="visually-hidden"
        type="file"
        accept="image/*"
        capture="environment"
        onChange={chosen}
      />
      <input id="photo-pick" class="visually-hidden" type="file" accept="image/*" onChange={chosen} />
    </>
  );
}
