/**
 * The upload of a photo already on screen: a slim bar over the top of the photo, so the
 * prompt and the tools stay in reach while the photo goes up (upload.ts). A failed upload
 * takes the prompt's place instead, with its Retry.
 */

import { t } from "../i18n";
import type { SessionView } from "../session";

/** Whether the upload's status takes the prompt's place: while no copy of the photo is shown
 * (the server's is awaited), and when the upload failed. */
export function uploadReplacesPrompt(view: SessionView): boolean {
  const { phase } = view.upload;
  if (phase === "idle") return false;
  return phase === "failed" || !view.photo?.pending;
}

export function UploadBar({ view }: { view: SessionView }) {
  if (!view.photo?.pending || view.upload.phase !== "uploading") return null;
  const percent = Math.round(view.upload.progress * 100);
  return (
    <div
      class="upload-bar"
      data-testid="upload-progress"
      role="progressbar"
      aria-valuenow={percent}
      aria-valuemin={0}
      aria-valuemax={100}
    >
      <div class="progress-bar" style={{ width: `${percent}%` }} />
      <span class="progress-text">{t("photo.sending", { percent })}</span>
    </div>
  );
}
