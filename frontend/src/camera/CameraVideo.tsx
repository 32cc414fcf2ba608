/**
 * The back camera's live picture, as both camera views show it (InAppCamera, LiveView):
 * muted, inline and playing by itself, which iOS Safari needs to play a camera stream in the
 * page; read out as what the camera sees. The view gives it its stream, class and test id.
 */

import type { JSX, Ref } from "preact";
import { t } from "../i18n";

type Props = Omit<JSX.HTMLAttributes<HTMLVideoElement>, "ref"> & { videoRef: Ref<HTMLVideoElement> };

export function CameraVideo({ videoRef, ...attributes }: Props) {
  return <video ref={videoRef} role="img" aria-label={t("camera.sees")} autoplay muted playsInline {...attributes} />;
}

/**
 * Closes the camera a view showed: the video lets go of the stream first, then its tracks
 * stop. Stopping a track under a playing video deadlocked WebKitGTK's web process (its
 * GStreamer pipeline reconfigured on the page's thread while the video's frame thread
 * waited on that same thread: docs/browsers.md); the video's own teardown first stops
 * taking frames.
 */
export function closeCamera(video: HTMLVideoElement | null, stream: MediaStream | null): void {
  if (video && video.srcObject) {
    video.pause();
    video.srcObject = null;
  }
  stream?.getTracks().forEach((track) => track.stop());
}
