/**
 * The photo view's transform over time (the math is viewTransform.ts): fitted to a new photo,
 * kept zoomed across a resize (rotation, bars), moved by gestures, zoomed onto a landmark to
 * re-check it, and gliding to bring the answer into view (reframe.ts), after the gesture in
 * progress when there is one. Free of Preact and the DOM: the view's hook (usePanZoom.ts)
 * measures and redraws, animation frames come in through {@link Frames}.
 */

import type { ViewNow } from "./pointers";
import { GLIDE_MS, easeInOut, frameTarget, glide, movedNoticeably, type Box, type Insets } from "./reframe";
import {
  centreOn,
  clampTransform,
  fitTransform,
  isFitted,
  type Point,
  type Size,
  type ViewTransform,
} from "./viewTransform";

/** A re-checked landmark is shown zoomed in at least this far, relative to the fitted view. */
export const FOCUS_ZOOM = 3;

/** Animation frames (the browser's requestAnimationFrame, or a test's). */
export interface Frames {
  request(step: (time: number) => void): number;
  cancel(id: number): void;
  now(): number;
}

export interface PanZoomState {
  /** The view's size, screen px; null until measured. */
  readonly view: Size | null;
  readonly transform: ViewTransform | null;
  /** Whether the view is gliding to the answer. */
  readonly gliding: boolean;
}

const NO_INSETS: Insets = { top: 0, right: 0, bottom: 0, left: 0 };

function sameSize(a: Size | null, b: Size): boolean {
  return !!a && a.width === b.width && a.height === b.height;
}

export class PanZoom {
  private current: PanZoomState = { view: null, transform: null, gliding: false };
  private glideFrame: number | null = null;
  /** The answer last brought into view, and one waiting for a gesture to end. */
  private shown: Box | null = null;
  private pending: Box | null = null;
  /** Screen px along each side covered by the status: the answer is brought into the rest. */
  insets: Insets = NO_INSETS;
  /** The person asked their phone for less motion (a11y/motion.ts): jump, never glide. */
  reducedMotion = false;

  constructor(
    private photo: Size,
    private readonly changed: (state: PanZoomState) => void,
    private readonly frames: Frames,
  ) {}

  get state(): PanZoomState {
    return this.current;
  }

  /** The view for the gestures; null until measured. */
  now(): ViewNow | null {
    const { view, transform } = this.current;
    return view && transform ? { size: view, transform, photo: this.photo } : null;
  }

  /** The view was measured at `size`: a zoomed view stays zoomed (clamped), a fitted one refits. */
  resize(size: Size): void {
    if (size.width < 1 || size.height < 1) return;
    const { view: before, transform } = this.current;
    if (sameSize(before, size)) return;
    const keepZoom = transform && before && !isFitted(transform, before, this.photo);
    const next = keepZoom ? clampTransform(transform, size, this.photo) : fitTransform(size, this.photo);
    this.update({ view: size, transform: next });
  }

  /** A new photo: the whole of it. */
  showPhoto(photo: Size): void {
    this.photo = photo;
    const { view } = this.current;
    if (view) this.update({ transform: fitTransform(view, photo) });
  }

  /** Where a gesture moved the view (already within limits). */
  set(transform: ViewTransform): void {
    this.update({ transform });
  }

  /** The whole photo again (the "whole photo" button). */
  fit(): void {
    const { view } = this.current;
    this.stopGlide();
    if (view) this.update({ transform: fitTransform(view, this.photo) });
  }

  /** Zoomed in on photo point `p` (a landmark to re-check), at least {@link FOCUS_ZOOM} times. */
  focus(p: Point): void {
    const { view, transform } = this.current;
    if (!view || !transform) return;
    this.stopGlide();
    const scale = Math.max(transform.scale, fitTransform(view, this.photo).scale * FOCUS_ZOOM);
    this.update({ transform: centreOn(p, scale, view, this.photo) });
  }

  /**
   * The answer's box (photo px), on every new or changed answer: brought into view when it is
   * new or moved noticeably; `busy`: a gesture is in progress, so it waits for the gesture's end.
   */
  answer(box: Box, busy: boolean): void {
    if (!this.now()) return;
    if (!movedNoticeably(this.shown, box)) return;
    this.shown = box;
    if (busy) this.pending = box;
    else this.bringIntoView(box);
  }

  /** After a gesture: an answer that arrived during it is brought into view now. */
  gestureEnded(): void {
    const box = this.pending;
    this.pending = null;
    if (box) this.bringIntoView(box);
  }

  /** Glide so that `box` (photo px) is in sight with room around it (reframe.ts). */
  bringIntoView(box: Box): void {
    const { view: size, transform: from } = this.current;
    if (!size || !from) return;
    const to = frameTarget(box, from, size, this.photo, this.insets);
    this.stopGlide();
    if (!to) return;
    if (this.reducedMotion) {
      this.update({ transform: clampTransform(to, size, this.photo) });
      return;
    }
    const start = this.frames.now();
    this.update({ gliding: true });
    const step = (time: number): void => {
      const k = easeInOut((time - start) / GLIDE_MS);
      const done = k >= 1;
      this.glideFrame = done ? null : this.frames.request(step);
      this.update({ transform: clampTransform(glide(from, to, k, size), size, this.photo), gliding: !done });
    };
    this.glideFrame = this.frames.request(step);
  }

  stopGlide(): void {
    if (this.glideFrame !== null) this.frames.cancel(this.glideFrame);
    this.glideFrame = null;
    if (this.current.gliding) this.update({ gliding: false });
  }

  private update(change: Partial<PanZoomState>): void {
    this.current = { ...this.current, ...change };
    this.changed(this.current);
  }
}
