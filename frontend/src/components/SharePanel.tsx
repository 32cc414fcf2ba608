/** The starter's screen until their friend joins: the code, its QR code, a share button. */

import type { ComponentChildren } from "preact";
import { useEffect, useState } from "preact/hooks";
import { t } from "../i18n";
import { codeGroups } from "../joinCode";
import type { QrCode } from "../qr";
import type { SessionController, SessionView } from "../session";
import type { SessionState } from "../types";
import { ShareIcon } from "./icons";
import { UploadStatus } from "./PhotoStep";

interface Props {
  controller: SessionController;
  view: SessionView;
  state: SessionState;
  top: ComponentChildren;
  /** The code ran out: start a new search instead (a new code). */
  onNewSearch: () => void;
}

async function copy(text: string): Promise<boolean> {
  try {
    if (navigator.clipboard && window.isSecureContext) {
      await navigator.clipboard.writeText(text);
      return true;
    }
  } catch {
    // fall through to the old way
  }
  // Plain http on a local network has no clipboard API: select and copy.
  const field = document.createElement("textarea");
  field.value = text;
  field.setAttribute("readonly", "");
  field.style.position = "fixed";
  field.style.opacity = "0";
  document.body.appendChild(field);
  field.select();
  let done = false;
  try {
    done = document.execCommand("copy");
  } catch {
    done = false;
  }
  field.remove();
  return done;
}

export function SharePanel({ controller, view, state, top, onNewSearch }: Props) {
  const [shared, setShared] = useState<string | null>(null);
  const code = state.join_code;
  const link = state.join_url;
  const [qr, setQr] = useState<QrCode | null>(null);
  // The QR encoder is a chunk of its own (only this panel needs it): fetched when shown.
  useEffect(() => {
    if (!link) return;
    let active = true;
    // With no signal the chunk may not come: the code and the link are shown without it.
    import("../qr").then(
      ({ makeQr }) => {
        if (active) setQr(makeQr(link));
      },
      () => undefined,
    );
    return () => {
      active = false;
    };
  }, [link]);

  const share = async (): Promise<void> => {
    if (!link) return;
    const text = t("share.shareText", { code: code ?? "" });
    if (typeof navigator.share === "function") {
      try {
        await navigator.share({ title: "Buddy Search", text, url: link });
        return;
      } catch (error) {
        if (error instanceof DOMException && error.name === "AbortError") return;
      }
    }
    setShared((await copy(link)) ? t("share.copied") : t("share.sendLink", { link }));
  };

  return (
    <main class="screen session share">
      <h1 class="visually-hidden">{t("a11y.shareScreenTitle")}</h1>
      {top}
      <section class="share-body">
        {code && link ? (
          <>
            <p class="label">{t("share.typeOrScan")}</p>
            <p class="code" data-testid="code" aria-label={t("share.codeAria", { digits: code.split("").join(" ") })}>
              {codeGroups(code).map((group, index) => (
                <span key={index}>{group}</span>
              ))}
            </p>
            {state.join_code_renewals > 0 && (
              <p class="note" data-testid="code-renewed" role="status">
                {t("share.renewed")}
              </p>
            )}
            {qr && (
              <svg
                class="qr"
                data-testid="qr"
                viewBox={`-4 -4 ${qr.size + 8} ${qr.size + 8}`}
                role="img"
                aria-label={t("share.qrAria")}
                shape-rendering="crispEdges"
              >
                <rect x="-4" y="-4" width={qr.size + 8} height={qr.size + 8} fill="#fff" />
                <path d={qr.path} fill="#000" />
              </svg>
            )}
            <button type="button" class="button secondary wide" data-testid="share" onClick={() => void share()}>
              <ShareIcon /> {t("share.shareLink")}
            </button>
            {shared && (
              <p class="note" role="status">
                {shared}
              </p>
            )}
            <p class="waiting" data-testid="waiting" role="status">
              <span class="spinner" aria-hidden="true" /> {t("share.waiting")}
            </p>
          </>
        ) : (
          <>
            <p class="error" role="alert">
              {t("share.ranOut")}
            </p>
            <p class="waiting" data-testid="waiting">
              {t("share.notJoined")}
            </p>
            <button type="button" class="button primary wide" onClick={onNewSearch}>
              {t("share.newCode")}
            </button>
          </>
        )}
      </section>
      <footer class="bottom-actions">
        {view.photo ? (
          <p class="note">{t("share.photoReady")}</p>
        ) : (
          <>
            <UploadStatus controller={controller} view={view} />
            <label class="button secondary huge" for="photo-input">
              {t("share.takeMeanwhile")}
            </label>
          </>
        )}
      </footer>
    </main>
  );
}
