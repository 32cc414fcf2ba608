/**
 * "Show me": the back camera's live view, full screen, with the answer's drawing over it
 * where the friend is in the world. The phone stands where it took its photo; its turn since
 * the shutter (orientation.ts) carries the server's drawing of the photo onto the video
 * (pointer.ts): the same brackets, label, curve and band, never a shape of the phone's own.
 * Out of view, an arrow at the screen's edge says which way to turn.
 *
 * The turn is measured from an anchor: the orientation at the in-app camera's shutter
 * (shutter.ts), or, for a photo without one (the gallery, a reload), a frame of this view
 * matched to the photo on the server (Align; Re-align at any time resets the gyroscope's
 * drift), taken once the phone holds still (still.ts). It says when its pointing is not to
 * be trusted (trust.ts): two minutes after the anchor, or once the phone has walked. The
 * camera, the orientation and the motion are read only while the view is open.
 *
 * It publishes what it drew for the browser tests: the frame's centre and the arrow's tip
 * (screen px), the video's size and focal length, the turn, the readings received, the
 * warning shown, and how still the phone was for the last frame sent (and how long Align
 * waited for it).
 */

import { useEffect, useRef, useState } from "preact/hooks";
import { ApiError } from "../api";
import { t } from "../i18n";
import { drawnLabel, errorText } from "../i18n/server";
import type { AnswerView } from "../answer";
import { CameraVideo, closeCamera } from "../camera/CameraVideo";
import { motionAccess } from "../camera/motion";
import { ArrowMark, DottedCurve, FONT, LEADER, LabelledFrame, MIN_FRAME_CSS, pathOf } from "../components/answerMarks";
import { loadShutterAnchor, saveShutterAnchor } from "../storage";
import type { Credentials, FrameShape, FriendInPhoto } from "../types";
import { agrees, checkNow, type FocalCheck } from "./focalCheck";
import { asMatrix, drawFrame, matchFrame } from "./frames";
import { anchorFromFrame, rotationAngleDeg, sinceShutter, type Matrix3, type Vector3 } from "./orientation";
import {
  cover,
  focalFrom35mm,
  homography,
  linesToScreen,
  liveFocal,
  photoToScreen,
  pointAt,
  pointAtCurve,
  screenPerPhotoPx,
  type Cover,
  type Point,
  type Pointing,
  type Size,
} from "./pointer";
import { OrientationSource, type Sample } from "./sensor";
import { lastShutterTime } from "./shutter";
import { StillWait, turnRate } from "./still";
import { mayHaveDrifted, motionReading, StepWatch } from "./trust";
import { arrowLabel, pointingText, type CurveKind } from "./words";

/** The back camera, 4:3 (the whole sensor, as photos are: pointer.ts's focal assumes it). */
const CONSTRAINTS: MediaStreamConstraints = {
  video: { facingMode: "environment", width: { ideal: 1920 }, height: { ideal: 1440 } },
  audio: false,
};
/** A photo's focal length when its answer gave none (a projective answer, cameras unknown):
 * a phone's main camera, 35 mm-equivalent. The server will not re-anchor such a photo. */
const TYPICAL_FOCAL_35MM = 26;
/** How far inside the screen's edge the arrow's tip stays, px. */
const EDGE_INSET = 40;
/** Screen px at the top kept for the words: no label goes there. */
const CLEAR_TOP = 96;

/** How often the view looks at the clock while open (for the drift's words), ms. */
const TICK_MS = 1000;
/** When each session's aligned anchor was read on this page (performance.now(), ms). */
const alignedAt = new Map<string, number>();
/** The anchor time of each session whose phone was seen walking since that anchor (the view
 * closed and opened again still says so, until a new photo or an Align; a walk while it is
 * closed goes unseen: no motion is read then). */
const walked = new Map<string, number>();

/** When the anchor the view opens with was read: the later of the shutter and an Align (the
 * stored anchor is the later one), else now. */
function anchorTime(sessionId: string): number {
  const times = [alignedAt.get(sessionId), lastShutterTime() ?? undefined].filter((t): t is number => t !== undefined);
  return times.length ? Math.max(...times) : performance.now();
}

/** The performance mark set when the first marker (the frame, the curve or the arrow) is
 * drawn over the playing video: the opening's end (the browser tests time it from the tap). */
export const MARKER_DRAWN = "show-me:marker-drawn";
/** ...and on the way: the view mounted, the camera's stream given, its first frame loaded. */
export const VIEW_OPENED = "show-me:view-opened";
export const CAMERA_STARTED = "show-me:camera-started";
export const FIRST_FRAME = "show-me:first-frame";

type Phase = "opening" | "live" | "failed";
type Aligning = { kind: "idle" } | { kind: "steadying" } | { kind: "sending" } | { kind: "refused"; message: string };
/** How often Align looks at the phone while it waits for it to hold still, ms. */
const LOOK_MS = 33;

interface Props {
  credentials: Credentials;
  answer: AnswerView;
  /** This phone's part of the answer (its friend_h, the focal length the answer used). */
  mine: FriendInPhoto;
  onClose: () => void;
}

export function LiveView({ credentials, answer, mine, onClose }: Props) {
  const [phase, setPhase] = useState<Phase>("opening");
  const [problem, setProblem] = useState<string>("");
  const [anchor, setAnchor] = useState<Matrix3 | null>(() => asMatrix(loadShutterAnchor(credentials.session_id)));
  const [anchoredAt, setAnchoredAt] = useState<number>(() => anchorTime(credentials.session_id));
  const [now, setNow] = useState<number>(() => performance.now());
  const [moved, setMoved] = useState(() => walked.get(credentials.session_id) === anchorTime(credentials.session_id));
  const steps = useRef(new StepWatch());
  const since = useRef(anchoredAt);
  since.current = anchoredAt;
  const [measured, setMeasured] = useState<number | null>(null);
  const [reading, setReading] = useState<Sample | null>(null);
  const [videoSize, setVideoSize] = useState<Size | null>(null);
  const [box, setBox] = useState<Size>({ width: window.innerWidth, height: window.innerHeight });
  const [aligning, setAligning] = useState<Aligning>({ kind: "idle" });
  // The video's focal length, checked once per opening when anchored at the shutter
  // (focalCheck.ts); the server cannot match a photo whose answer has no focal length.
  const [focalCheck, setFocalCheck] = useState<FocalCheck>(() => (anchor && mine.focal_px ? "waiting" : "off"));
  /** The last frame sent: the phone's turn rate then (degrees a second) and the wait, ms. */
  const [sent, setSent] = useState<{ rate: number | null; waited: number } | null>(null);
  const video = useRef<HTMLVideoElement>(null);
  const [playing, setPlaying] = useState(false);
  const drawnOnce = useRef(false);
  const stage = useRef<HTMLDivElement>(null);
  const source = useRef<OrientationSource | null>(null);

  // The camera, the orientation and the motion while open; all stop on close.
  useEffect(() => {
    performance.mark(VIEW_OPENED);
    const element = video.current;
    let closed = false;
    let stream: MediaStream | null = null;
    const sensor = new OrientationSource((sample) => {
      if (!closed) setReading(sample);
    });
    source.current = sensor;
    const onMotion = (event: DeviceMotionEvent): void => {
      const motion = motionReading(event, performance.now());
      if (!motion || closed) return;
      steps.current.push(motion);
      if (steps.current.moved) {
        walked.set(credentials.session_id, since.current);
        setMoved(true);
      }
    };
    const tick = window.setInterval(() => setNow(performance.now()), TICK_MS);
    if (motionAccess() !== "denied") {
      sensor.start();
      window.addEventListener("devicemotion", onMotion);
    }
    const open = async (): Promise<void> => {
      try {
        if (!navigator.mediaDevices?.getUserMedia) throw new DOMException("no camera API", "NotFoundError");
        stream = await navigator.mediaDevices.getUserMedia(CONSTRAINTS);
        performance.mark(CAMERA_STARTED);
        if (closed) {
          stream.getTracks().forEach((track) => track.stop());
          return;
        }
        if (element) {
          element.srcObject = stream;
          await element.play().catch(() => undefined);
        }
        setPhase("live");
      } catch {
        if (closed) return;
        setProblem(t("live.cameraFailed"));
        setPhase("failed");
      }
    };
    void open();
    return () => {
      closed = true;
      sensor.stop();
      window.removeEventListener("devicemotion", onMotion);
      window.clearInterval(tick);
      source.current = null;
      closeCamera(element, stream);
    };
  }, []);

  useEffect(() => {
    const element = stage.current;
    if (!element) return;
    const measure = (): void => setBox({ width: element.clientWidth, height: element.clientHeight });
    measure();
    const observer = new ResizeObserver(measure);
    observer.observe(element);
    return () => observer.disconnect();
  }, []);

  const drawing = answer.drawing;
  const photo: Size | null = drawing ? { width: drawing.width, height: drawing.height } : null;
  // The answer's own focal length for this photo, px, as the server matches frames with it.
  const photoFocal = photo ? (mine.focal_px ?? focalFrom35mm(TYPICAL_FOCAL_35MM, photo)) : null;
  const videoFocal = photo && photoFocal && videoSize ? liveFocal(photoFocal, photo, videoSize, measured) : null;

  const align = async (): Promise<void> => {
    const element = video.current;
    const sensor = source.current;
    if (!element || !videoSize || !sensor?.latest() || aligning.kind === "sending" || aligning.kind === "steadying") return;
    setAligning({ kind: "steadying" });
    // The frame of a still phone (still.ts), with the reading of its moment; else the
    // stillest seen in the wait.
    const started = performance.now();
    const wait = new StillWait(started);
    let kept: Grabbed | null = null;
    let chosen: Grabbed | null = null;
    while (!chosen) {
      const now = performance.now();
      const rate = turnRate(sensor.readings(), now);
      const look = wait.look(now, rate);
      const at = sensor.latest();
      if (!at) break; // the view closed
      if (look === "send") chosen = { canvas: drawFrame(element, videoSize), at, rate, waited: now - started };
      else if (look === "best") chosen = kept ? { ...kept, waited: now - started } : { canvas: drawFrame(element, videoSize), at, rate, waited: now - started };
      else if (look === "keep") kept = { canvas: drawFrame(element, videoSize), at, rate, waited: 0 };
      if (!chosen) await new Promise((resolve) => window.setTimeout(resolve, LOOK_MS));
    }
    if (!chosen) {
      setAligning({ kind: "idle" });
      return;
    }
    setSent({ rate: chosen.rate, waited: chosen.waited });
    const at = chosen.at;
    setAligning({ kind: "sending" });
    try {
      const { rotation, focalPerLongSide } = await matchFrame(credentials, chosen.canvas);
      const aligned = anchorFromFrame(at, rotation);
      setAnchor(aligned);
      // Kept as the photo's anchor on this page: the view opened again starts from it.
      saveShutterAnchor(credentials.session_id, aligned);
      // The view matches the photo: the drift starts again, and the phone stands where it was.
      const time = performance.now();
      alignedAt.set(credentials.session_id, time);
      setAnchoredAt(time);
      setNow(time);
      steps.current.reset();
      walked.delete(credentials.session_id);
      setMoved(false);
      setMeasured(focalPerLongSide);
      setAligning({ kind: "idle" });
    } catch (error) {
      // The last anchor stays: a refused match moves nothing.
      const notMatched = error instanceof ApiError && error.reason === "frame_not_matched";
      // A server without the endpoint (or a proxy's page) has no sentence of its own.
      const bare = error instanceof ApiError && error.code.startsWith("http_");
      const message = notMatched ? t("live.notMatched") : bare ? t("live.unavailable") : errorText(error);
      setAligning({ kind: "refused", message });
    }
  };

  // The quiet check: one frame of a still phone facing its photo's view; its focal length
  // kept when the match agrees with the sensors. Align, tapped meanwhile, measures it too.
  useEffect(() => {
    const element = video.current;
    const sensor = source.current;
    // Once it is over (or off), nothing more on each reading.
    if (focalCheck !== "waiting") return;
    if (phase !== "live" || !playing || !anchor || !reading || !element || !videoSize || !sensor || aligning.kind !== "idle") return;
    const sensed = sinceShutter(anchor, reading);
    if (!checkNow(focalCheck, turnRate(sensor.readings(), performance.now()), rotationAngleDeg(sensed))) return;
    setFocalCheck("sending");
    matchFrame(credentials, drawFrame(element, videoSize)).then(
      ({ rotation, focalPerLongSide }) => {
        if (!source.current) return; // closed meanwhile
        const kept = agrees(rotation, sensed);
        if (kept) setMeasured(focalPerLongSide);
        setFocalCheck(kept ? "measured" : "disagreed");
      },
      () => setFocalCheck("refused"),
    );
  });

  const ready = phase === "live" && anchor && reading && photo && photoFocal && videoSize && videoFocal;
  const layer = ready ? place(sinceShutter(anchor, reading), photo, photoFocal, videoSize, videoFocal, box, mine, drawing?.curve?.polylines ?? null) : null;
  // The curve alone (no point): its arrow and words are the curve's (or the level's).
  const curve: CurveKind | null = drawing?.curve && !friendOf(mine) ? (mine.level ? "level" : "curve") : null;

  let words: string;
  if (phase === "failed") words = problem;
  else if (aligning.kind === "steadying") words = t("live.holdStill");
  else if (aligning.kind === "sending") words = t("live.aligning");
  else if (aligning.kind === "refused") words = aligning.message;
  else if (motionAccess() === "denied") words = t("live.noMotion");
  else if (!anchor) words = t("live.align");
  else if (!reading) words = t("live.noSensor");
  else words = pointingText(layer?.pointing ?? null, curve);
  // The first marker over the playing video: marked in the animation frame that paints it.
  const drawn = Boolean(layer && (layer.pointing || drawing?.curve));
  useEffect(() => {
    if (drawnOnce.current || !playing || !drawn) return;
    drawnOnce.current = true;
    requestAnimationFrame(() => performance.mark(MARKER_DRAWN));
  });

  // Said above the pointing while it points: the phone walked away, or the anchor is old.
  const steady = phase === "live" && anchor && reading && (aligning.kind === "idle" || aligning.kind === "refused");
  const warning = !steady ? null : moved ? "moved" : mayHaveDrifted(anchoredAt, now) ? "drift" : null;

  return (
    <div
      class="live"
      role="dialog"
      aria-modal="true"
      aria-label={t("live.dialog")}
      data-testid="live-view"
      data-phase={phase}
      data-anchored={String(Boolean(anchor))}
      data-readings={String(source.current?.count ?? 0)}
      data-warning={warning ?? "none"}
      data-aligning={aligning.kind}
      data-focal-check={focalCheck}
      data-sent-rate={sent ? (sent.rate?.toFixed(2) ?? "unknown") : undefined}
      data-sent-wait={sent ? sent.waited.toFixed(0) : undefined}
    >
      <div class="live-stage" ref={stage}>
        <CameraVideo
          videoRef={video}
          class="live-video"
          data-testid="live-video"
          onLoadedData={() => {
            performance.mark(FIRST_FRAME);
            setPlaying(true);
          }}
          onPlaying={() => setPlaying(true)}
          onLoadedMetadata={(event) => {
            const v = event.currentTarget;
            setVideoSize({ width: v.videoWidth, height: v.videoHeight });
          }}
          onResize={(event) => {
            const v = event.currentTarget;
            setVideoSize({ width: v.videoWidth, height: v.videoHeight });
          }}
        />
        {layer && drawing && (
          <svg
            class="live-layer"
            width={box.width}
            height={box.height}
            aria-hidden="true"
            data-testid="live-layer"
            data-video={`${videoSize?.width ?? 0}x${videoSize?.height ?? 0}`}
            data-video-focal={videoFocal?.toFixed(2)}
            data-turn={layer.rotation.map((row) => row.map((v) => v.toFixed(4)).join(",")).join(";")}
          >
            {drawing.curve && (
              <LiveCurve lines={linesToScreen(layer.h, layer.cover, drawing.curve.polylines)} band={(drawing.curve.halfwidth ?? 0) * layer.perPhotoPx} />
            )}
            {drawing.frame && layer.pointing?.kind === "in-view" && <LiveFrame frame={drawing.frame} layer={layer} />}
            {layer.pointing?.kind === "off-view" && <EdgeArrow pointing={layer.pointing} towards={curve ? "curve" : "friend"} />}
          </svg>
        )}
      </div>
      <p class="live-note" data-testid="live-note" role="status">
        {warning && (
          <strong class="live-warning" data-testid="live-warning">
            {t(`live.${warning}`)}{" "}
          </strong>
        )}
        {words}
        <span class="live-stay">{t("live.stay")}</span>
      </p>
      <div class="live-bar">
        <button type="button" class="button secondary" data-testid="live-close" onClick={onClose}>
          {t("live.close")}
        </button>
        <button
          type="button"
          class={`button ${anchor && !warning ? "secondary" : "primary"}`}
          data-testid="live-align"
          disabled={phase !== "live" || !reading || aligning.kind === "sending" || aligning.kind === "steadying"}
          onClick={() => void align()}
        >
          {anchor ? t("live.realign") : t("live.alignButton")}
        </button>
      </div>
    </div>
  );
}

interface Layer {
  rotation: Matrix3;
  h: Matrix3;
  cover: Cover;
  perPhotoPx: number;
  pointing: Pointing | null;
}

/** The friend in the photo, homogeneous (w < 0: behind its camera), or null (no point). */
function friendOf(mine: FriendInPhoto): Vector3 | null {
  if (mine.friend_h) return [mine.friend_h[0], mine.friend_h[1], mine.friend_h[2]];
  return mine.friend ? [mine.friend[0], mine.friend[1], 1] : null;
}

/** The photo's drawing placed on the live screen by the turn `rotation`: where the friend
 * is, or, with no point, whether the curve is on the screen and which way it is if not. */
function place(
  rotation: Matrix3,
  photo: Size,
  photoFocal: number,
  video: Size,
  videoFocal: number,
  box: Size,
  mine: FriendInPhoto,
  curve: ReadonlyArray<ReadonlyArray<readonly number[]>> | null,
): Layer {
  const h = homography(rotation, photoFocal, photo, videoFocal, video);
  const c = cover(video, box);
  const friend = friendOf(mine);
  const pointing = friend ? pointAt(h, c, video, friend, EDGE_INSET) : curve ? pointAtCurve(h, c, video, videoFocal, curve, EDGE_INSET) : null;
  return { rotation, h, cover: c, perPhotoPx: screenPerPhotoPx(c, photoFocal, videoFocal), pointing };
}

/** The server's brackets, turned onto the screen, spread to a finger's size at the least;
 * "friend" on its leader above them (below when the words are there). */
function LiveFrame({ frame, layer }: { frame: FrameShape; layer: Layer }) {
  const centre = photoToScreen(layer.h, layer.cover, frame.centre);
  if (!centre) return null;
  const spread = (half: number): number => Math.max(1, MIN_FRAME_CSS / (layer.perPhotoPx * half));
  const [sx, sy] = [spread(frame.half[0]), spread(frame.half[1])];
  const brackets = frame.brackets
    .map((line) =>
      line
        .map((p) => photoToScreen(layer.h, layer.cover, p))
        .filter((p): p is Point => p !== null)
        .map((p) => ({ x: centre.x + sx * (p.x - centre.x), y: centre.y + sy * (p.y - centre.y) })),
    )
    .filter((line) => line.length > 1);
  const ys = brackets.flat().map((p) => p.y);
  const top = Math.min(centre.y, ...ys);
  const bottom = Math.max(centre.y, ...ys);
  return (
    <g data-testid="live-frame" data-x={centre.x.toFixed(2)} data-y={centre.y.toFixed(2)}>
      <LabelledFrame
        brackets={pathOf(brackets, (p) => p)}
        centre={centre}
        top={top}
        bottom={bottom}
        above={top - LEADER - FONT >= CLEAR_TOP}
        label={drawnLabel(frame.label)}
      />
    </g>
  );
}

/** The curve the friend is on, dotted, in its band when it has one (screen px). */
function LiveCurve({ lines, band }: { lines: Point[][]; band: number }) {
  return (
    <g data-testid="live-curve" data-pieces={String(lines.length)}>
      <DottedCurve path={pathOf(lines, (p) => p)} band={2 * band} stretch={null} />
    </g>
  );
}

/** An arrow inside the screen's edge towards the friend (or the nearest part of their
 * curve), saying which way to turn. */
function EdgeArrow({ pointing, towards }: { pointing: Extract<Pointing, { kind: "off-view" }>; towards: "friend" | "curve" }) {
  const { at, angle } = pointing;
  return (
    <g data-testid="live-arrow" data-turn={pointing.turn} data-towards={towards} data-x={at.x.toFixed(2)} data-y={at.y.toFixed(2)}>
      {/* The words inside the arrow's tail, kept on the screen. */}
      <ArrowMark tip={at} angle={angle} label={arrowLabel(pointing)} labelBack={30} />
    </g>
  );
}

/** A frame drawn for Align, with the reading of its moment and how still the phone was. */
interface Grabbed {
  canvas: HTMLCanvasElement;
  at: Sample;
  rate: number | null;
  waited: number;
}
