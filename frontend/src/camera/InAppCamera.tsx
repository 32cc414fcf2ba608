/**
 * The camera inside the page: the back camera's live view, a big shutter, and which way is
 * down and which way the lens looks read at the shutter (motion.ts, gravity.ts, heading.ts)
 * and sent with the photo. The phone's own
 * camera app and the gallery stay one tap away (PhotoStep.tsx): they send no sensors.
 *
 * Opened from a tap: where the browser asks for motion access (iOS), the app first says in
 * its own words why, once per page, and carries on without sensors if refused.
 */

import { useEffect, useRef, useState } from "preact/hooks";
import { t } from "../i18n";
import type { SensorFields } from "../types";
import { markShutter } from "../live/shutter";
import { CameraVideo, closeCamera } from "./CameraVideo";
import { takePicture } from "./capture";
import type { GravityReading } from "./gravity";
import type { HeadingReading } from "./heading";
import { answerMotion, motionAccess, MotionRecorder } from "./motion";


/** The highest resolution the phone gives (a 12 MP sensor's 4:3); the back camera. */
const CONSTRAINTS: MediaStreamConstraints = {
  video: { facingMode: "environment", width: { ideal: 4032 }, height: { ideal: 3024 } },
  audio: false,
};
/** How often the words under the view follow the phone's stillness. */
const STILLNESS_POLL_MS = 250;

type Phase = "ask" | "opening" | "live" | "taking";

interface Props {
  /** The photo taken, with what was read at the shutter (null: nothing to send). */
  onPhoto: (file: File, sensors: SensorFields | null) => void;
  /** Closed, by the person (no message) or because the camera cannot open (why). */
  onClose: (problem: string | null) => void;
}

/** Why the camera did not open, in words a person can act on. */
export function cameraProblem(error: unknown): string {
  const name = error instanceof DOMException || error instanceof Error ? error.name : "";
  if (name === "NotAllowedError" || name === "SecurityError") {
    return t("camera.notAllowed");
  }
  if (name === "NotFoundError" || name === "OverconstrainedError") {
    return t("camera.notFound");
  }
  return t("camera.failed");
}

/** The words under the live view for what the phone knows of down right now. */
export function stillnessWords(access: "granted" | "denied", reading: GravityReading): string {
  if (access === "denied") return t("camera.motionOff");
  if (reading.kind === "moving") return t("camera.moving");
  if (reading.kind === "none") return t("camera.noDown");
  return t("camera.downKnown");
}

/**
 * The form fields of the readings at the shutter: only a still phone's, and the heading only
 * beside down.
 */
export function sensorFields(reading: GravityReading, heading: HeadingReading): SensorFields | null {
  if (reading.kind !== "still") return null;
  const down = { gravity: reading.gravity, gravity_sigma_deg: reading.sigmaDeg };
  return heading.kind === "still" ? { ...down, heading: heading.heading, heading_sigma_deg: heading.sigmaDeg } : down;
}

export function InAppCamera({ onPhoto, onClose }: Props) {
  const [phase, setPhase] = useState<Phase>(motionAccess() === "ask" ? "ask" : "opening");
  const [access, setAccess] = useState<"granted" | "denied">(motionAccess() === "denied" ? "denied" : "granted");
  const [words, setWords] = useState<string>("");
  const video = useRef<HTMLVideoElement>(null);
  const stream = useRef<MediaStream | null>(null);
  const motion = useRef(new MotionRecorder());

  // The camera opens once the motion question is answered, and everything stops on close.
  useEffect(() => {
    if (phase !== "opening") return;
    let closed = false;
    const open = async (): Promise<void> => {
      try {
        if (!navigator.mediaDevices?.getUserMedia) throw new DOMException("no camera API", "NotFoundError");
        const opened = await navigator.mediaDevices.getUserMedia(CONSTRAINTS);
        if (closed) {
          opened.getTracks().forEach((track) => track.stop());
          return;
        }
        stream.current = opened;
        if (video.current) {
          video.current.srcObject = opened;
          await video.current.play().catch(() => undefined); // autoplay does it where play() is refused
        }
        // The sensor only now, while the camera is open.
        if (access === "granted") motion.current.start();
        setPhase("live");
      } catch (error) {
        if (!closed) onClose(cameraProblem(error));
      }
    };
    void open();
    return () => {
      closed = true;
    };
  }, [phase]);

  useEffect(() => {
    const recorder = motion.current;
    const element = video.current;
    return () => {
      recorder.stop();
      closeCamera(element, stream.current);
      stream.current = null;
    };
  }, []);

  useEffect(() => {
    if (phase !== "live") return;
    const follow = (): void => setWords(stillnessWords(access, motion.current.reading()));
    follow();
    const timer = window.setInterval(follow, STILLNESS_POLL_MS);
    return () => window.clearInterval(timer);
  }, [phase, access]);

  const answer = async (ask: boolean): Promise<void> => {
    setAccess(await answerMotion(ask));
    setPhase("opening");
  };

  const shoot = async (): Promise<void> => {
    const track = stream.current?.getVideoTracks()[0];
    if (phase !== "live" || !video.current || !track) return;
    // Down and the heading at the moment of the tap, before the picture (takePhoto can take a while).
    const sensors = access === "granted" ? sensorFields(motion.current.reading(), motion.current.heading()) : null;
    markShutter(); // the orientation too, kept on the phone for "Show me" (live/shutter.ts)
    setPhase("taking");
    try {
      const file = await takePicture(video.current, track);
      onPhoto(file, sensors);
    } catch (error) {
      onClose(cameraProblem(error));
    }
  };

  return (
    <div class="camera" role="dialog" aria-modal="true" aria-label={t("camera.dialog")} data-testid="in-app-camera" data-phase={phase}>
      <CameraVideo videoRef={video} class="camera-view" data-testid="camera-view" />
      {phase === "ask" ? (
        <div class="camera-ask" data-testid="motion-question">
          <p>{t("camera.motionAsk")}</p>
          <div class="camera-ask-actions">
            <button type="button" class="button primary wide" data-testid="motion-allow" onClick={() => void answer(true)}>
              {t("camera.allow")}
            </button>
            <button type="button" class="button secondary wide" data-testid="motion-skip" onClick={() => void answer(false)}>
              {t("camera.notNow")}
            </button>
          </div>
        </div>
      ) : (
        <p class="camera-note" data-testid="camera-note" role="status">
          {phase === "opening" ? t("camera.opening") : phase === "taking" ? t("camera.taking") : words}
        </p>
      )}
      <div class="camera-bar">
        <button type="button" class="button secondary" data-testid="camera-close" onClick={() => onClose(null)}>
          {t("camera.close")}
        </button>
        <button
          type="button"
          class="camera-shutter"
          data-testid="shutter"
          aria-label={t("camera.shutter")}
          disabled={phase !== "live"}
          onClick={() => void shoot()}
        />
      </div>
    </div>
  );
}
