import { t } from "../i18n";
import type { Ending } from "../session";

export function EndedScreen({ ending, onStart }: { ending: Ending; onStart: () => void }) {
  return (
    <main class="screen ended" data-testid="ended">
      <div class="ended-body">
        <h1>{t("ended.title")}</h1>
        <p class="lead">
          {ending === "deleted" ? t("ended.deleted") : t("ended.expired")}
        </p>
      </div>
      <div class="bottom-actions">
        <button type="button" class="button primary huge" onClick={onStart}>
          {t("ended.startAgain")}
        </button>
      </div>
    </main>
  );
}
