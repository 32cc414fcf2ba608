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
