/**
 * The tap surface: the stored photo, zoomable and pannable, with this phone's marks drawn
 * on top at a constant size, and the loupe while a finger presses. It publishes its view
 * transform as data attributes (data-scale, data-tx, data-ty): photo pixel (x, y) is at
 * (rect.left + tx + scale * x, rect.top + ty + scale * y).
 */

import { useEffect, useLayoutEffect, useRef, useState } from "preact/hooks";
import {
  IDLE,
  fingerDown,
  fingerUp,
  fingersMove,
  loupeTarget,
  pressTarget,
  wheelFactor,
  type Gesture,
  type Grab,
  type Outcome,
} from "../gestures";
import { clipLine, type Landmark, type TapSet } from "../landmarks";
import { LOUPE_SIZE, labelPositions, loupePosition, loupeZoom } from "../markLayout";
import { FRIEND_COLOUR, OUTLINE_COLOUR, landmarkColour } from "../palette";
import { tapSigma } from "../precision";
import type { Tap } from "../session";
import {
  centreOn,
  clampTransform,
  fitTransform,
  isFitted,
  isInsidePhoto,
  toPhoto,
  toScreen,
  zoomAbout,
  type Point,
  type Size,
  type ViewTransform,
} from "../viewTransform";
import { FitIcon } from "./icons";
import { OverlayLayer } from "./OverlayLayer";

export interface Focus {
  id: number;
  nonce: number;
}

interface Props {
  photoUrl: string;
  photoSize: Size;
  /** The server's drawing of the answer, shown over the photo (same pixels). */
  overlayUrl: string | null;
  taps: TapSet;
  selected: number | null;
  suspects: readonly number[];
  linePoint: Point | null;
  /** Photo points no label may cover (the answer's star). */
  keepClear: readonly Point[];
  focus: Focus | null;
  /** A tap, with its precision at the zoom and aim it was made with. */
  onTap: (at: Tap) => void;
  onMove: (id: number, to: Tap) => void;
  onSelect: (id: number | null) => void;
}

/** Mouse events this soon after a touch are the browser's imitation of it: ignored. */
const TOUCH_MOUSE_GAP_MS = 1000;

function sameSize(a: Size | null, b: Size | null): boolean {
  return !!a && !!b && a.width === b.width && a.height === b.height;
}

export function PhotoView(props: Props) {
  const { photoSize, taps } = props;
  const box = useRef<HTMLDivElement>(null);
  const image = useRef<HTMLImageElement>(null);
  const [view, setView] = useState<Size | null>(null);
  const [transform, setTransform] = useState<ViewTransform | null>(null);
  const [gesture, setGesture] = useState<Gesture>(IDLE);
  const [loaded, setLoaded] = useState(false);
  // What the native event handlers (attached once) need to read now.
  const live = useRef({
    props,
    view: null as Size | null,
    transform: null as ViewTransform | null,
    gesture: IDLE as Gesture,
    fingers: new Map<number, Point>(),
    lastTouch: 0,
  });
  live.current.props = props;

  const applyTransform = (next: ViewTransform): void => {
    live.current.transform = next;
    setTransform(next);
  };
  const applyGesture = (next: Gesture): void => {
    live.current.gesture = next;
    setGesture(next);
  };

  // Measure the view before the first paint, and on every resize (rotation, bars).
  useLayoutEffect(() => {
    const element = box.current;
    if (!element) return;
    const measure = (): void => {
      const rect = element.getBoundingClientRect();
      if (rect.width < 1 || rect.height < 1) return;
      const size = { width: rect.width, height: rect.height };
      const { view: before, transform: current, props: now } = live.current;
      if (sameSize(before, size)) return;
      live.current.view = size;
      setView(size);
      const keepZoom = current && before && !isFitted(current, before, now.photoSize);
      applyTransform(
        keepZoom ? clampTransform(current, size, now.photoSize) : fitTransform(size, now.photoSize),
      );
    };
    measure();
    const observer = new ResizeObserver(measure);
    observer.observe(element);
    return () => observer.disconnect();
  }, []);

  // A new photo: fitted again.
  useEffect(() => {
    setLoaded(false);
    const size = live.current.view;
    if (size) applyTransform(fitTransform(size, photoSize));
  }, [props.photoUrl, photoSize.width, photoSize.height]);

  // "Re-check #3": zoom to that landmark.
  useEffect(() => {
    const { focus } = props;
    const size = live.current.view;
    const current = live.current.transform;
    const landmark = taps.landmarks.find((l) => l.id === focus?.id);
    if (!focus || !size || !current || !landmark) return;
    const scale = Math.max(current.scale, fitTransform(size, photoSize).scale * 3);
    applyTransform(centreOn(landmark, scale, size, photoSize));
  }, [props.focus?.nonce]);

  // Touch, mouse and wheel, attached natively: touch handlers must be able to
  // preventDefault (no page scroll or zoom, no imitated mouse events).
  useEffect(() => {
    const element = box.current;
    if (!element) return;
    const local = (x: number, y: number): Point => {
      const rect = element.getBoundingClientRect();
      return { x: x - rect.left, y: y - rect.top };
    };
    const isUi = (target: EventTarget | null): boolean =>
      target instanceof Element && target.closest("[data-ui]") !== null;

    const grabAt = (target: EventTarget | null): Grab | null => {
      const label = target instanceof Element ? target.closest("[data-landmark-label]") : null;
      const id = Number(label?.getAttribute("data-id"));
      const { props: now, transform: t } = live.current;
      const landmark = now.taps.landmarks.find((l) => l.id === id);
      return landmark && t ? { id, from: toScreen(t, landmark) } : null;
    };

    const finish = (outcome: Outcome): void => {
      const { transform: t, props: now } = live.current;
      if (!t) return;
      if (outcome.kind === "place") {
        const at = toPhoto(t, outcome.at);
        if (isInsidePhoto(at, now.photoSize)) now.onTap({ ...at, sigma: tapSigma(t.scale, outcome.aim) });
      } else if (outcome.kind === "move") {
        const at = toPhoto(t, outcome.to);
        now.onMove(outcome.id, {
          x: Math.min(Math.max(at.x, 0), now.photoSize.width),
          y: Math.min(Math.max(at.y, 0), now.photoSize.height),
          sigma: tapSigma(t.scale, outcome.aim),
        });
      } else if (outcome.kind === "select") {
        now.onSelect(now.selected === outcome.id ? null : outcome.id);
      }
    };

    const moved = (): void => {
      const { gesture: g, fingers, transform: t, view: v, props: now } = live.current;
      if (!t || !v) return;
      const zoomed = !isFitted(t, v, now.photoSize);
      const next = fingersMove(g, fingers, t, v, now.photoSize, zoomed);
      if (next.transform) applyTransform(next.transform);
      if (next.gesture !== g) applyGesture(next.gesture);
    };

    // --- touch ---
    const onTouchStart = (event: TouchEvent): void => {
      if (isUi(event.target)) return;
      event.preventDefault();
      live.current.lastTouch = Date.now();
      const { fingers } = live.current;
      for (const touch of [...event.touches, ...event.changedTouches]) {
        if (!fingers.has(touch.identifier)) fingers.set(touch.identifier, local(touch.clientX, touch.clientY));
      }
      const t = live.current.transform;
      if (!t) return;
      let g = live.current.gesture;
      for (const touch of event.changedTouches) {
        g = fingerDown(g, fingers, touch.identifier, grabAt(event.target), t, false, event.timeStamp);
      }
      applyGesture(g);
    };
    const onTouchMove = (event: TouchEvent): void => {
      if (live.current.fingers.size === 0) return;
      event.preventDefault();
      live.current.lastTouch = Date.now();
      for (const touch of [...event.touches, ...event.changedTouches]) {
        if (live.current.fingers.has(touch.identifier)) {
          live.current.fingers.set(touch.identifier, local(touch.clientX, touch.clientY));
        }
      }
      moved();
    };
    const onTouchEnd = (event: TouchEvent): void => {
      const { fingers } = live.current;
      if (fingers.size === 0) return;
      event.preventDefault();
      live.current.lastTouch = Date.now();
      const cancelled = event.type === "touchcancel";
      const lifted: number[] = [];
      for (const touch of event.changedTouches) {
        if (fingers.has(touch.identifier)) {
          fingers.set(touch.identifier, local(touch.clientX, touch.clientY));
          lifted.push(touch.identifier);
        }
      }
      // Fingers the browser no longer lists are up too.
      const still = new Set([...event.touches].map((touch) => touch.identifier));
      for (const id of fingers.keys()) if (!still.has(id) && !lifted.includes(id)) lifted.push(id);
      if (lifted.length) moved(); // the lift point counts (a drag's last position)
      let g = live.current.gesture;
      for (const id of lifted) {
        fingers.delete(id);
        const next = fingerUp(g, fingers, id, cancelled, event.timeStamp);
        g = next.gesture;
        finish(next.outcome);
      }
      applyGesture(g);
    };

    // --- mouse ---
    const onMouseMove = (event: MouseEvent): void => {
      live.current.fingers.set(0, local(event.clientX, event.clientY));
      moved();
    };
    const onMouseUp = (event: MouseEvent): void => {
      window.removeEventListener("mousemove", onMouseMove);
      window.removeEventListener("mouseup", onMouseUp);
      const { fingers } = live.current;
      if (!fingers.has(0)) return;
      fingers.set(0, local(event.clientX, event.clientY));
      moved();
      fingers.delete(0);
      const next = fingerUp(live.current.gesture, fingers, 0, false, event.timeStamp);
      applyGesture(next.gesture);
      finish(next.outcome);
    };
    const onMouseDown = (event: MouseEvent): void => {
      if (event.button !== 0 || isUi(event.target)) return;
      if (Date.now() - live.current.lastTouch < TOUCH_MOUSE_GAP_MS) return;
      const t = live.current.transform;
      if (!t || live.current.fingers.size > 0) return;
      event.preventDefault();
      live.current.fingers.set(0, local(event.clientX, event.clientY));
      const grab = grabAt(event.target);
      applyGesture(fingerDown(live.current.gesture, live.current.fingers, 0, grab, t, true, event.timeStamp));
      window.addEventListener("mousemove", onMouseMove);
      window.addEventListener("mouseup", onMouseUp);
    };
    const onWheel = (event: WheelEvent): void => {
      const { transform: t, view: v, props: now } = live.current;
      if (!t || !v) return;
      event.preventDefault();
      const factor = wheelFactor(event.deltaY, event.deltaMode);
      applyTransform(zoomAbout(t, factor, local(event.clientX, event.clientY), v, now.photoSize));
    };

    // iOS Safari's own page zoom would fight the pinch.
    const onGesture = (event: Event): void => event.preventDefault();
    element.addEventListener("gesturestart", onGesture);
    const options = { passive: false } as const;
    element.addEventListener("touchstart", onTouchStart, options);
    element.addEventListener("touchmove", onTouchMove, options);
    element.addEventListener("touchend", onTouchEnd, options);
    element.addEventListener("touchcancel", onTouchEnd, options);
    element.addEventListener("mousedown", onMouseDown);
    element.addEventListener("wheel", onWheel, options);
    return () => {
      element.removeEventListener("touchstart", onTouchStart);
      element.removeEventListener("touchmove", onTouchMove);
      element.removeEventListener("touchend", onTouchEnd);
      element.removeEventListener("touchcancel", onTouchEnd);
      element.removeEventListener("mousedown", onMouseDown);
      element.removeEventListener("wheel", onWheel);
      element.removeEventListener("gesturestart", onGesture);
      window.removeEventListener("mousemove", onMouseMove);
      window.removeEventListener("mouseup", onMouseUp);
    };
  }, []);

  const ready = view !== null && transform !== null;
  const attributes = ready
    ? {
        "data-photo-width": String(photoSize.width),
        "data-photo-height": String(photoSize.height),
        "data-scale": String(transform.scale),
        "data-tx": String(transform.tx),
        "data-ty": String(transform.ty),
      }
    : {};

  return (
    <div
      ref={box}
      class="photo-view"
      data-testid="photo-view"
      role="application"
      aria-label="Your photo: tap to mark, two fingers to zoom"
      {...attributes}
    >
      {ready && (
        <Drawing
          {...props}
          view={view}
          transform={transform}
          gesture={gesture}
          image={image}
          loaded={loaded}
          onLoaded={() => setLoaded(true)}
          onFit={() => applyTransform(fitTransform(view, photoSize))}
        />
      )}
    </div>
  );
}

interface DrawingProps extends Props {
  view: Size;
  transform: ViewTransform;
  gesture: Gesture;
  image: { current: HTMLImageElement | null };
  loaded: boolean;
  onLoaded: () => void;
  onFit: () => void;
}

/** The picture: photo, answer overlay, marks, loupe. */
function Drawing(props: DrawingProps) {
  const { view, transform: t, gesture, taps, photoSize, selected, suspects } = props;
  const layer = `width:${photoSize.width}px;height:${photoSize.height}px;transform:translate(${t.tx}px,${t.ty}px) scale(${t.scale})`;
  const screen = (p: Point): Point => toScreen(t, p);

  // A grabbed landmark is drawn where the finger is taking it.
  const dragged =
    gesture.kind === "press" && gesture.grab && gesture.moved
      ? { id: gesture.grab.id, at: toPhoto(t, pressTarget(gesture)) }
      : null;
  const landmarks: Landmark[] = taps.landmarks.map((l) =>
    dragged && l.id === dragged.id ? { ...l, ...dragged.at } : l,
  );
  const line = taps.friend_line ? clipLine(taps.friend_line, photoSize) : null;
  const friends: Point[] = taps.friend ? [taps.friend] : [];
  const labels = labelPositions(
    landmarks.map((l) => ({ id: l.id, at: screen(l) })),
    view,
    [...friends, ...props.keepClear].map(screen),
  );
  const target = loupeTarget(gesture);
  const zoomed = !isFitted(t, view, photoSize);

  return (
    <>
      <img
        ref={props.image}
        class="layer"
        src={props.photoUrl}
        style={layer}
        alt="Your photo"
        draggable={false}
        onLoad={props.onLoaded}
      />
      {props.overlayUrl && <OverlayLayer url={props.overlayUrl} style={layer} />}
      <svg class="lines" width={view.width} height={view.height} aria-hidden="true">
        {line && (
          <g>
            <line {...ends(screen(line[0]), screen(line[1]))} stroke={OUTLINE_COLOUR} stroke-width="6" />
            <line {...ends(screen(line[0]), screen(line[1]))} stroke={FRIEND_COLOUR} stroke-width="3" />
          </g>
        )}
        {landmarks.map((l) => {
          const p = screen(l);
          const label = labels.get(l.id) ?? p;
          return (
            <line
              key={l.id}
              {...ends(p, label)}
              stroke={landmarkColour(l.id)}
              stroke-width="2"
              stroke-dasharray="2 3"
            />
          );
        })}
      </svg>
      {props.linePoint && <div class="line-point" style={at(screen(props.linePoint))} />}
      {taps.friend && (
        <div class="friend-mark" data-testid="friend-mark" style={at(screen(taps.friend))}>
          <span>Friend</span>
        </div>
      )}
      {landmarks.map((l) => {
        const p = screen(l);
        const label = labels.get(l.id) ?? p;
        const colour = landmarkColour(l.id);
        const suspect = suspects.includes(l.id);
        const state = `${l.id === selected ? " selected" : ""}${suspect ? " suspect" : ""}`;
        return (
          <div key={l.id}>
            <div class={`lm-point${state}`} style={`${at(p)};--c:${colour}`} />
            <div
              class={`lm-label${state}`}
              data-testid="landmark"
              data-id={String(l.id)}
              data-landmark-label=""
              style={`${at(label)};--c:${colour}`}
            >
              {l.id}
              {suspect ? "?" : ""}
              <span class="lm-hit" />
            </div>
          </div>
        );
      })}
      {target && props.image.current && (
        <Loupe
          target={target}
          view={view}
          transform={t}
          image={props.image.current}
          photoSize={photoSize}
          landmarks={landmarks}
          marks={friends}
        />
      )}
      {!props.loaded && <p class="photo-loading">Loading photo...</p>}
      {zoomed && (
        <button type="button" class="fit-button" data-ui="" aria-label="Whole photo" onClick={props.onFit}>
          <FitIcon />
        </button>
      )}
    </>
  );
}

function at(p: Point): string {
  return `left:${p.x}px;top:${p.y}px`;
}

function ends(a: Point, b: Point): { x1: number; y1: number; x2: number; y2: number } {
  return { x1: a.x, y1: a.y, x2: b.x, y2: b.y };
}

interface LoupeProps {
  target: Point;
  view: Size;
  transform: ViewTransform;
  image: HTMLImageElement;
  photoSize: Size;
  landmarks: readonly Landmark[];
  marks: readonly Point[];
}

/** The magnified photo around the finger, with a cross-hair on the exact spot. */
function Loupe({ target, view, transform, image, photoSize, landmarks, marks }: LoupeProps) {
  const canvas = useRef<HTMLCanvasElement>(null);
  const ratio = Math.min(3, window.devicePixelRatio || 1);
  const size = LOUPE_SIZE;
  const place = loupePosition(target, view);

  useLayoutEffect(() => {
    const context = canvas.current?.getContext("2d");
    if (!context) return;
    const zoom = loupeZoom(transform.scale);
    const centre = toPhoto(transform, target);
    context.setTransform(1, 0, 0, 1, 0, 0);
    context.fillStyle = "#000";
    context.fillRect(0, 0, size * ratio, size * ratio);
    const offset = (value: number): number => ratio * (size / 2 - value * zoom);
    context.setTransform(ratio * zoom, 0, 0, ratio * zoom, offset(centre.x), offset(centre.y));
    context.imageSmoothingEnabled = zoom < 3;
    if (image.complete && image.naturalWidth > 0) {
      context.drawImage(image, 0, 0, photoSize.width, photoSize.height);
    }
    context.setTransform(ratio, 0, 0, ratio, 0, 0);
    const inLoupe = (p: Point): Point => ({
      x: size / 2 + (p.x - centre.x) * zoom,
      y: size / 2 + (p.y - centre.y) * zoom,
    });
    const ring = (p: Point, colour: string, radius: number): void => {
      const q = inLoupe(p);
      context.beginPath();
      context.arc(q.x, q.y, radius, 0, 2 * Math.PI);
      context.lineWidth = 4;
      context.strokeStyle = OUTLINE_COLOUR;
      context.stroke();
      context.lineWidth = 2;
      context.strokeStyle = colour;
      context.stroke();
    };
    for (const l of landmarks) ring(l, landmarkColour(l.id), 8);
    for (const m of marks) ring(m, FRIEND_COLOUR, 12);
    // The cross-hair: open in the middle so the exact spot stays visible.
    const c = size / 2;
    const arms: Array<[number, number, number, number]> = [
      [c - 30, c, c - 5, c],
      [c + 5, c, c + 30, c],
      [c, c - 30, c, c - 5],
      [c, c + 5, c, c + 30],
    ];
    for (const [width, colour] of [
      [4, OUTLINE_COLOUR],
      [2, "#ffffff"],
    ] as const) {
      context.lineWidth = width;
      context.strokeStyle = colour;
      context.beginPath();
      for (const [x1, y1, x2, y2] of arms) {
        context.moveTo(x1, y1);
        context.lineTo(x2, y2);
      }
      context.stroke();
    }
  });

  return (
    <canvas
      ref={canvas}
      class="loupe"
      width={size * ratio}
      height={size * ratio}
      style={`left:${place.x}px;top:${place.y}px;width:${size}px;height:${size}px`}
      aria-hidden="true"
    />
  );
}
