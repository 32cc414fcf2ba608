/**
 * The file inputs behind the big photo buttons (labels point at them): one opens the
 * camera, one the gallery. Always in the page while in a session.
 */

import { t } from "../i18n";
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
    <section aria-label={t("a11y.photoInputs")}>
      <input
        id="photo-input"
        data-testid="photo-input"
        class="visually-hidden"
        type="file"
        accept="image/*"
        capture="environment"
        aria-label={t("a11y.takePhoto")}
        onChange={chosen}
      />
      <input id="photo-pick" class="visually-hidden" type="file" accept="image/*" aria-label={t("a11y.pickPhoto")} onChange={chosen} />
    </section>
  );
}
