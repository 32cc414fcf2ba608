/** The bar on top of every session screen: the other phone, saving, new photo, delete. */

import { useState } from "preact/hooks";
import { t } from "../i18n";
import { LanguageSwitch } from "../i18n/LanguageSwitch";
import type { SessionController, SessionView } from "../session";
import { otherRole } from "../types";
import { CameraIcon, TrashIcon } from "./icons";

const SAVE_WORDS = { saved: "top.saved", saving: "top.saving", error: "top.notSaved" } as const;

export function TopBar({ controller, view }: { controller: SessionController; view: SessionView }) {
  const [confirming, setConfirming] = useState(false);
  const [deleting, setDeleting] = useState(false);
  const { state, credentials } = view;
  const other = otherRole(credentials.role);
  const peer = state?.participants[other];
  const online = peer?.online ?? false;
  const peerWords = !peer?.joined ? t("top.friendAway") : online ? t("top.friendOnline") : t("top.friendOffline");

  return (
    <header class="top-bar">
      {view.kept ? (
        // Reloaded with no signal: what is shown is this phone's copy (session/sync.ts),
        // and whether the friend is online is not known.
        <span class="peer off" data-testid="offline" role="status">
          <span class="dot" aria-hidden="true" />
          <span class="peer-words">{t("top.offline")}</span>
        </span>
      ) : (
        <span class={`peer ${online ? "on" : "off"}`} data-testid="peer-online" data-online={String(online)}>
          <span class="dot" aria-hidden="true" />
          <span class="peer-words">{peerWords}</span>
        </span>
      )}
      {view.stream === "down" && !view.kept && (
        <span class="reconnecting" data-testid="reconnecting" role="status">
          {t("top.reconnecting")}
        </span>
      )}
      <span class="spacer" />
      <LanguageSwitch compact />
      {view.photo && (
        <>
          <button
            type="button"
            class={`save-state ${view.save.status}`}
            data-testid="save-state"
            data-state={view.save.status}
            title={view.save.message ?? undefined}
            onClick={() => controller.taps.retrySave()}
          >
            {view.save.status === "saved" ? (
              // Saved, the quiet state: a check mark, its word for screen readers only, so
              // that "Friend online" is said in full beside it on a 390 px phone.
              <span class="visually-hidden">{t(SAVE_WORDS.saved)}</span>
            ) : (
              t(SAVE_WORDS[view.save.status])
            )}
          </button>
          <label class="icon-button" for="photo-input" title={t("top.newPhoto")}>
            <CameraIcon />
          </label>
        </>
      )}
      <button
        type="button"
        class="icon-button danger"
        data-testid="delete-session"
        aria-label={t("top.deleteNow")}
        title={t("top.deleteNow")}
        onClick={() => setConfirming(true)}
      >
        <TrashIcon />
      </button>
      {confirming && (
        <div class="sheet-backdrop" role="dialog" aria-modal="true" aria-labelledby="delete-title">
          <div class="sheet">
            <h2 id="delete-title">{t("top.deleteTitle")}</h2>
            <p>{t("top.deleteBody")}</p>
            {view.deleteError && (
              <p class="error" role="alert">
                {view.deleteError}
              </p>
            )}
            <button
              type="button"
              class="button danger huge"
              data-testid="confirm-delete"
              disabled={deleting}
              onClick={async () => {
                setDeleting(true);
                const done = await controller.deletion.deleteNow();
                if (!done) setDeleting(false);
              }}
            >
              {deleting ? t("top.deleting") : t("top.deleteNow")}
            </button>
            <button
              type="button"
              class="button secondary huge"
              onClick={() => {
                controller.deletion.clearDeleteError();
                setConfirming(false);
              }}
            >
              {t("top.keepSearching")}
            </button>
          </div>
        </div>
      )}
    </header>
  );
}
