/** The starter's screen until their friend joins: the code, its QR code, a share button. */

import type { ComponentChildren } from "preact";
import { useMemo, useState } from "preact/hooks";
import { SHARE_SCREEN_TITLE } from "../a11y/labels";
import { codeGroups } from "../joinCode";
import { makeQr } from "../qr";
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
  const qr = useMemo(() => (link ? makeQr(link) : null), [link]);

  const share = async (): Promise<void> => {
    if (!link) return;
    const text = `Join my Buddy Search: code ${code ?? ""}`;
    if (typeof navigator.share === "function") {
      try {
        await navigator.share({ title: "Buddy Search", text, url: link });
        return;
      } catch (error) {
        if (error instanceof DOMException && error.name === "AbortError") return;
      }
    }
    setShared((await copy(link)) ? "Link copied: paste it to your friend." : `Send this link: ${link}`);
  };

  return (
    <main class="screen session share">
      <h1 class="visually-hidden">{SHARE_SCREEN_TITLE}</h1>
      {top}
      <section class="share-body">
        {code && link ? (
          <>
            <p class="label">Your friend types this code, or scans it</p>
            <p class="code" data-testid="code" aria-label={`Code ${code.split("").join(" ")}`}>
              {codeGroups(code).map((group, index) => (
                <span key={index}>{group}</span>
              ))}
            </p>
            {state.join_code_renewals > 0 && (
              <p class="note" data-testid="code-renewed" role="status">
                New code: someone typed wrong codes for your search, so the last one no longer
                works. Give your friend this one.
              </p>
            )}
            {qr && (
              <svg
                class="qr"
                data-testid="qr"
                viewBox={`-4 -4 ${qr.size + 8} ${qr.size + 8}`}
                role="img"
                aria-label="QR code of the join link"
                shape-rendering="crispEdges"
              >
                <rect x="-4" y="-4" width={qr.size + 8} height={qr.size + 8} fill="#fff" />
                <path d={qr.path} fill="#000" />
              </svg>
            )}
            <button type="button" class="button secondary wide" data-testid="share" onClick={() => void share()}>
              <ShareIcon /> Share link
            </button>
            {shared && (
              <p class="note" role="status">
                {shared}
              </p>
            )}
            <p class="waiting" data-testid="waiting" role="status">
              <span class="spinner" aria-hidden="true" /> Waiting for your friend...
            </p>
          </>
        ) : (
          <>
            <p class="error" role="alert">
              The code ran out before your friend joined.
            </p>
            <p class="waiting" data-testid="waiting">
              Your friend has not joined yet.
            </p>
            <button type="button" class="button primary wide" onClick={onNewSearch}>
              New code
            </button>
          </>
        )}
      </section>
      <footer class="bottom-actions">
        {view.photo ? (
          <p class="note">Your photo is ready.</p>
        ) : (
          <>
            <UploadStatus controller={controller} view={view} />
            <label class="button secondary huge" for="photo-input">
              Take your photo meanwhile
            </label>
          </>
        )}
      </footer>
    </main>
  );
}
