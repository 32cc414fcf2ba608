/**
 * The photo view's input: Pointer Events (fingers, a mouse, a pen) and the wheel, fed to the
 * gesture state machine (gestures.ts). One code path for every engine: Chromium, WebKit
 * (iOS Safari since 13) and Firefox deliver touch, mouse and pen as pointer events, so no
 * touch and mouse handlers side by side and no guessing which mouse events imitate a touch.
 *
 * Why our own and not a gesture library: @use-gesture (10.3, the maintained one) picks its
 * pinch input by feature detection and listens for no pinch at all where the browser reports
 * no touch screen (`pinchConfigResolver.device`), so the same page would pinch in one engine
 * and not in another; and it runs drag and pinch as separate handlers, while here a press
 * turns into a pinch when a second finger lands and then places nothing until every finger
 * is up. What is left to do by hand is a map of pointers, below.
 *
 * Points are client coordinates on the way in and screen points relative to the view
 * (viewTransform.ts) from here on.
 */

import {
  IDLE,
  fingerDown,
  fingerUp,
  fingersMove,
  wheelFactor,
  type Gesture,
  type Grab,
  type Outcome,
} from "./gestures";
import { isFitted, zoomAbout, type Insets, type Point, type Size, type ViewTransform } from "./viewTransform";

/** What the gestures read of a pointer event (a PointerEvent is one). */
export interface PointerInput {
  readonly pointerId: number;
  /** "touch", "mouse" or "pen"; a pen aims as a finger does (it gets the loupe). */
  readonly pointerType: string;
  /** The first pointer of its type down (a mouse is always primary). */
  readonly isPrimary: boolean;
  /** 0: the main button (a finger, a pen's tip, the left mouse button). */
  readonly button: number;
  readonly clientX: number;
  readonly clientY: number;
  /** ms, any clock: only differences count. */
  readonly timeStamp: number;
  readonly target: EventTarget | null;
}

/** What the wheel reads of a wheel event. */
export interface WheelInput {
  readonly clientX: number;
  readonly clientY: number;
  readonly deltaY: number;
  readonly deltaMode: number;
}

/** The view as it is now: null before it was measured. */
export interface ViewNow {
  readonly transform: ViewTransform;
  readonly size: Size;
  readonly photo: Size;
  /** The bands covered by words and controls: the photo's edge may come in that far. */
  readonly slack: Insets;
}

/** The photo view's side: what the gestures read of it and tell it. */
export interface GestureHost {
  now(): ViewNow | null;
  /** The view's top-left corner in client coordinates. */
  origin(): Point;
  /** The landmark whose label `target` is (or is inside), at screen point `from`. */
  grabAt(target: EventTarget | null, transform: ViewTransform): Grab | null;
  /** A pinch, a pan or the wheel moved the photo. */
  transformed(transform: ViewTransform): void;
  /** The gesture changed (the loupe and a dragged mark follow it). */
  changed(gesture: Gesture): void;
  /** A pointer lifted with an effect, on the view as it is now. */
  finished(outcome: Outcome, view: ViewNow): void;
  /** The first pointer went down (a glide in progress stops). */
  started(): void;
  /** The last pointer lifted. */
  ended(): void;
}

/**
 * The pointers on the view and the gesture they make. Each method returns whether the event
 * was the view's (the caller then cancels the browser's default: no text selection, no
 * page zoom).
 */
export class PointerGestures {
  private readonly fingers = new Map<number, Point>();
  private gesture: Gesture = IDLE;

  constructor(private readonly host: GestureHost) {}

  /** Whether a pointer is down on the view. */
  get active(): boolean {
    return this.fingers.size > 0;
  }

  down(event: PointerInput): boolean {
    const view = this.host.now();
    if (!view || event.button !== 0) return false;
    if (event.isPrimary && this.fingers.size > 0) {
      // A primary pointer goes down only when no other of its type is: those still listed
      // lost their "up" (the system took them away), so they count as cancelled.
      for (const id of [...this.fingers.keys()]) this.lift(id, true, event.timeStamp);
    }
    if (this.fingers.size === 0) this.host.started();
    const mouse = event.pointerType === "mouse";
    this.fingers.set(event.pointerId, this.local(event));
    const grab = this.host.grabAt(event.target, view.transform);
    this.set(fingerDown(this.gesture, this.fingers, event.pointerId, grab, view.transform, mouse, event.timeStamp));
    return true;
  }

  move(event: PointerInput): boolean {
    if (!this.fingers.has(event.pointerId)) return false;
    this.fingers.set(event.pointerId, this.local(event));
    this.moved();
    return true;
  }

  /** A pointer lifted (`cancelled`: the system took it away, as pointercancel says). */
  up(event: PointerInput, cancelled = false): boolean {
    if (!this.fingers.has(event.pointerId)) return false;
    if (!cancelled) {
      // The lift point counts (a drag's last position); a cancel's point need not be real.
      this.fingers.set(event.pointerId, this.local(event));
      this.moved();
    }
    this.lift(event.pointerId, cancelled, event.timeStamp);
    return true;
  }

  /** The wheel zooms about the pointer. */
  wheel(event: WheelInput): boolean {
    const view = this.host.now();
    if (!view) return false;
    this.host.started();
    const factor = wheelFactor(event.deltaY, event.deltaMode);
    this.host.transformed(zoomAbout(view.transform, factor, this.local(event), view.size, view.photo, view.slack));
    return true;
  }

  private lift(id: number, cancelled: boolean, time: number): void {
    this.fingers.delete(id);
    const next = fingerUp(this.gesture, this.fingers, id, cancelled, time);
    this.set(next.gesture);
    const view = this.host.now();
    if (view && next.outcome.kind !== "none") this.host.finished(next.outcome, view);
    if (this.fingers.size === 0) this.host.ended();
  }

  private moved(): void {
    const view = this.host.now();
    if (!view) return;
    const zoomed = !isFitted(view.transform, view.size, view.photo);
    const next = fingersMove(this.gesture, this.fingers, view.transform, view.size, view.photo, zoomed, view.slack);
    if (next.transform) this.host.transformed(next.transform);
    this.set(next.gesture);
  }

  private set(gesture: Gesture): void {
    if (gesture === this.gesture) return;
    this.gesture = gesture;
    this.host.changed(gesture);
  }

  private local(event: { clientX: number; clientY: number }): Point {
    const origin = this.host.origin();
    return { x: event.clientX - origin.x, y: event.clientY - origin.y };
  }
}

/**
 * Listen on `element` for pointers going down and the wheel, and on `scope` (the window) for
 * their moves and lifts, so a mouse dragged off the view still ends its drag. No pointer
 * capture: `setPointerCapture` throws for a pointer the browser did not make itself (the
 * tests' touch pointers in WebKit, whose driver has no touch), and a window listener sees
 * the same events. Returns what stops listening.
 */
export function listen(element: EventTarget, scope: EventTarget, gestures: PointerGestures): () => void {
  const taken = (handled: boolean, event: Event): void => {
    if (handled && event.cancelable) event.preventDefault();
  };
  const onDown = (event: Event): void => taken(gestures.down(event as PointerEvent), event);
  const onMove = (event: Event): void => taken(gestures.move(event as PointerEvent), event);
  const onUp = (event: Event): void => taken(gestures.up(event as PointerEvent), event);
  const onCancel = (event: Event): void => void gestures.up(event as PointerEvent, true);
  const onWheel = (event: Event): void => taken(gestures.wheel(event as WheelEvent), event);
  // iOS Safari's own page zoom would fight the pinch.
  const onGesture = (event: Event): void => event.preventDefault();
  // Chromium moves a touch onto a nearby element that takes taps (its touch adjustment),
  // and only click and mouse-button listeners make an element take taps, pointer listeners
  // do not. The view listens for click, and does nothing with it, so that it competes: a
  // touch on the photo beside a control (PhotoView.tsx) stays on the photo.
  const onClick = (): void => undefined;
  const active = { passive: false } as const;
  const pairs: Array<[EventTarget, string, (event: Event) => void]> = [
    [element, "pointerdown", onDown],
    [element, "wheel", onWheel],
    [element, "gesturestart", onGesture],
    [element, "click", onClick],
    [scope, "pointermove", onMove],
    [scope, "pointerup", onUp],
    [scope, "pointercancel", onCancel],
  ];
  for (const [target, type, handler] of pairs) target.addEventListener(type, handler, active);
  return () => {
    for (const [target, type, handler] of pairs) target.removeEventListener(type, handler);
  };
}
