/** Taking (or picking) the photo of the other side, and sending it. */

import type { ComponentChildren } from "preact";
import { useEffect, useRef, useState } from "preact/hooks";
import { useFocusOnChange } from "../a11y/focus";
import { InAppCamera } from "../camera/InAppCamera";
import { startShutterOrientation, stopShutterOrientation, takeShutterAnchor } from "../live/shutter";
import { t } from "../i18n";
import { lensReader } from "../lens";
import type { SessionController, SessionView } from "../session";
import { CameraIcon } from "./icons";

export function UploadStatus({ controller, view }: { controller: SessionController; view: SessionView }) {
  const { upload } = view;
  if (upload.phase === "preparing") {
    return (
      <p class="note" role="status">
        {t("photo.preparing")}
      </p>
    );
  }
  if (upload.phase === "uploading") {
    const percent = Math.round(upload.progress * 100);
    return (
      <div class="progress" data-testid="upload-progress" role="progressbar" aria-valuenow={percent} aria-valuemin={0} aria-valuemax={100}>
        <div class="progress-bar" style={{ width: `${percent}%` }} />
        <span class="progress-text">{t("photo.sending", { percent })}</span>
      </div>
    );
  }
  if (upload.phase === "failed") {
    return (
      <div class="upload-failed">
        <p class="error" data-testid="upload-error" role="alert">
          {upload.message}
        </p>
        {upload.retryable ? (
          <button type="button" class="button primary wide" data-testid="upload-retry" onClick={() => void controller.photo.retry()}>
            {t("photo.retry")}
          </button>
        ) : (
          view.photo && (
            <button type="button" class="button secondary wide" onClick={() => controller.photo.dismiss()}>
              {t("photo.keepOld")}
            </button>
          )
        )}
      </div>
    );
  }
  return null;
}

interface Props {
  controller: SessionController;
  view: SessionView;
  top: ComponentChildren;
}

export function PhotoStep({ controller, view, top }: Props) {
  const busy = view.upload.phase === "preparing" || view.upload.phase === "uploading";
  const [camera, setCamera] = useState<"closed" | "open">("closed");
  const [cameraProblem, setCameraProblem] = useState<string | null>(null);
  // The screen changed (the friend joined, or the link was opened): its title is read first.
  const title = useRef<HTMLHeadingElement>(null);
  useFocusOnChange(() => title.current, "photo-step");
  // The lens reader fetched while there is a signal: the photo may be chosen without one.
  useEffect(() => void lensReader().catch(() => undefined), []);
  // The orientation is read while the camera is open, for "Show me" (live/shutter.ts).
  useEffect(() => {
    if (camera !== "open") return;
    startShutterOrientation();
    return stopShutterOrientation;
  }, [camera]);
  return (
    <main class="screen session photo-step">
      {top}
      <section class="photo-step-body">
        <div class="photo-hint" aria-hidden="true">
          <CameraIcon />
        </div>
        <h1 ref={title} tabIndex={-1} data-testid="photo-step-title">
          {t("photo.title")}
        </h1>
        <p class="lead">
          {t("photo.lead")}
        </p>
      </section>
      <footer class="bottom-actions">
        <UploadStatus controller={controller} view={view} />
        {cameraProblem && (
          <p class="error" data-testid="camera-problem" role="alert">
            {cameraProblem}
          </p>
        )}
        <label class={`button primary huge ${busy ? "disabled" : ""}`} for="photo-input">
          {view.upload.phase === "failed" && !view.upload.retryable ? t("photo.takeAnother") : t("photo.take")}
        </label>
        <label class={`button secondary wide ${busy ? "disabled" : ""}`} for="photo-pick">
          {t("photo.gallery")}
        </label>
        <button
          type="button"
          class="button secondary wide"
          data-testid="open-camera"
          disabled={busy}
          onClick={() => {
            setCameraProblem(null);
            setCamera("open");
          }}
        >
          {t("photo.inAppCamera")}
        </button>
      </footer>
      {camera === "open" && (
        <InAppCamera
          onPhoto={(file, sensors) => {
            setCamera("closed");
            void controller.photo.choose(file, sensors, takeShutterAnchor());
          }}
          onClose={(problem) => {
            setCamera("closed");
            setCameraProblem(problem);
          }}
        />
      )}
    </main>
  );
}
