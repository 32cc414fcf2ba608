/**
 * The photo view's transform over time (the math is viewTransform.ts): fitted to a new photo,
 * kept zoomed across a resize (rotation, bars), moved by gestures, zoomed onto a landmark to
 * re-check it, and gliding to bring the answer into view (reframe.ts), after the gesture in
 * progress when there is one. Free of Preact and the DOM: the view's hook (usePanZoom.ts)
 * measures and redraws, animation frames come in through {@link Frames}.
 */

import type { ViewNow } from "./pointers";
import { GLIDE_MS, boxInView, easeInOut, frameTarget, glide, movedNoticeably, overhang, shownPart, slackFor, type Box } from "./reframe";
import {
  NO_INSETS,
  centreOn,
  clampTransform,
  fitTransform,
  isFitted,
  openingTransform,
  type Insets,
  type Point,
  type Size,
  type ViewTransform,
} from "./viewTransform";

/** A re-checked landmark is shown zoomed in at least this far, relative to the fitted view. */
export const FOCUS_ZOOM = 3;
/** After a finger lifts, the view keeps still this long before it moves to the answer: it
 * never moves under a finger about to tap again (landmarks tapped one after another while
 * the answer comes in), ms. */
export const QUIET_MS = 1200;

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
  /** Whether an answer waits for the fingers' quiet ({@link QUIET_MS}) to be brought into view. */
  readonly settling?: boolean;
}


function sameSize(a: Size | null, b: Size): boolean {
  return !!a && a.width === b.width && a.height === b.height;
}

export class PanZoom {
  private current: PanZoomState = { view: null, transform: null, gliding: false };
  private glideFrame: number | null = null;
  /** The answer last brought into view, and one waiting for a gesture to end. */
  private shown: Box | null = null;
  private pending: Box | null = null;
  /** Screen px along each side covered by words and controls, and a margin: the answer is
   * brought into the rest, and the photo's edge may come in that far (clampTransform). */
  private insets: Insets = NO_INSETS;
  /** How far the answer last brought into view reaches past the photo's edges, photo px. */
  private reach: Insets = NO_INSETS;
  /** Whether the view is as the photo opened: nothing has moved it since. */
  private opening = true;
  /** What the photo opens around (photo px; its middle when null): see showPhoto. */
  private around: Point | null = null;
  /** When the last gesture ended (frames' clock, ms), and the frame waiting for the quiet. */
  private lastLift = Number.NEGATIVE_INFINITY;
  private quietFrame: number | null = null;
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
    return view && transform ? { size: view, transform, photo: this.photo, slack: this.slack(transform.scale) } : null;
  }

  /**
   * The bands covered along the view's sides changed (the status grew, the phone turned):
   * the answer last brought into view is brought out from under them again; `busy`: after
   * the gesture in progress.
   */
  setInsets(insets: Insets, busy = false): void {
    const before = this.insets;
    this.insets = insets;
    const same = (["top", "right", "bottom", "left"] as const).every((side) => before[side] === insets[side]);
    if (!same) this.keepInView(busy);
  }

  /**
   * The view was measured at `size`: a photo as it opened opens again at the new size
   * (openingTransform), a zoomed view stays zoomed (clamped), a fitted one refits.
   */
  resize(size: Size): void {
    if (size.width < 1 || size.height < 1) return;
    const { view: before, transform } = this.current;
    if (sameSize(before, size)) return;
    const keepZoom = !this.opening && transform && before && !isFitted(transform, before, this.photo);
    const next = keepZoom
      ? clampTransform(transform, size, this.photo, this.slack(transform.scale))
      : this.opening
        ? openingTransform(size, this.photo, this.around)
        : fitTransform(size, this.photo);
    this.update({ view: size, transform: next });
    this.keepInView(false);
  }

  /** How far the photo's edge may come in at `scale`: the bands, and what the answer's frame
   * needs beyond them (reframe.ts's slackFor). */
  private slack(scale: number): Insets {
    return slackFor(this.insets, this.reach, scale);
  }

  /** The answer last brought into view, out of sight or under a band now: shown again. */
  private keepInView(busy: boolean): void {
    const { view, transform } = this.current;
    const box = this.shown;
    if (!view || !transform || !box) return;
    if (boxInView(shownPart(box, this.photo), transform, view, this.insets)) return;
    this.request(box, busy);
  }

  /** Bring `box` into view: now, or once the gesture in progress (`busy`) has ended and the
   * view has been quiet for {@link QUIET_MS}. */
  private request(box: Box, busy: boolean): void {
    this.pending = box;
    if (busy) return;
    const tick = (time: number): void => {
      this.quietFrame = null;
      if (time < this.lastLift + QUIET_MS) {
        this.quietFrame = this.frames.request(tick);
        return;
      }
      const waiting = this.pending;
      this.pending = null;
      this.update({ settling: false });
      if (waiting) this.bringIntoView(waiting);
    };
    if (this.quietFrame !== null) return;
    if (this.frames.now() >= this.lastLift + QUIET_MS) tick(this.frames.now());
    else {
      this.quietFrame = this.frames.request(tick);
      this.update({ settling: true });
    }
  }

  /**
   * A new photo: as it opens (openingTransform), the whole of it unless that is small; then
   * filled around `around` (photo px), the part that matters when it opens (the friend this
   * phone marked, the next landmark's band), or its middle.
   */
  showPhoto(photo: Size, around: Point | null = null): void {
    this.photo = photo;
    this.opening = true;
    this.around = around;
    const { view } = this.current;
    if (view) this.update({ transform: openingTransform(view, photo, around) });
  }

  /** Where a gesture moved the view (already within limits). */
  set(transform: ViewTransform): void {
    this.opening = false;
    this.update({ transform });
  }

  /** The whole photo again (the "whole photo" button). */
  fit(): void {
    const { view } = this.current;
    this.opening = false;
    this.stopGlide();
    if (view) this.update({ transform: fitTransform(view, this.photo) });
  }

  /** Zoomed in on photo point `p` (a landmark to re-check), at least {@link FOCUS_ZOOM} times. */
  focus(p: Point): void {
    const { view, transform } = this.current;
    if (!view || !transform) return;
    this.opening = false;
    this.stopGlide();
    const scale = Math.max(transform.scale, fitTransform(view, this.photo).scale * FOCUS_ZOOM);
    this.update({ transform: centreOn(p, scale, view, this.photo, this.slack(scale)) });
  }

  /**
   * The answer's box (photo px), on every new or changed answer: brought into view when it is
   * new or moved noticeably; `busy`: a gesture is in progress, so it waits for the gesture's end.
   */
  answer(box: Box, busy: boolean): void {
    if (!this.now()) return;
    if (!movedNoticeably(this.shown, box)) return;
    this.shown = box;
    this.request(box, busy);
  }

  /** A finger landed: a glide stops where it is, and an answer waiting stays waiting. */
  gestureStarted(): void {
    this.stopGlide();
    if (this.quietFrame !== null) this.frames.cancel(this.quietFrame);
    this.quietFrame = null;
    if (this.current.settling) this.update({ settling: false });
  }

  /** After a gesture: an answer that arrived during it is brought into view once the view
   * has been quiet for {@link QUIET_MS}. */
  gestureEnded(): void {
    this.lastLift = this.frames.now();
    const box = this.pending;
    if (box) this.request(box, false);
  }

  /** Glide so that `box` (photo px) is in sight with room around it (reframe.ts). */
  bringIntoView(box: Box): void {
    const { view: size, transform: from } = this.current;
    if (!size || !from) return;
    const to = frameTarget(box, from, size, this.photo, this.insets);
    this.reach = overhang(shownPart(box, this.photo), this.photo);
    this.stopGlide();
    if (!to) return;
    this.opening = false;
    if (this.reducedMotion) {
      this.update({ transform: clampTransform(to, size, this.photo, this.slack(to.scale)) });
      return;
    }
    const start = this.frames.now();
    this.update({ gliding: true });
    const step = (time: number): void => {
      const k = easeInOut((time - start) / GLIDE_MS);
      const done = k >= 1;
      this.glideFrame = done ? null : this.frames.request(step);
      const at = glide(from, to, k, size);
      this.update({ transform: clampTransform(at, size, this.photo, this.slack(at.scale)), gliding: !done });
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
