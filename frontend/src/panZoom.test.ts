import { describe, expect, it } from "vitest";
import { FOCUS_ZOOM, PanZoom, QUIET_MS, type Frames, type PanZoomState } from "./panZoom";
import { GLIDE_MS, boxInView, frameTarget, type Box } from "./reframe";
import { NO_INSETS, fitTransform, isFitted, openingTransform, toScreen, zoomAbout, type Size } from "./viewTransform";

const phone = { width: 412, height: 560 };
const photo = { width: 640, height: 480 };
/** The phone turned to landscape. */
const turned = { width: 560, height: 412 };

/** Animation frames run by hand: `run(ms)` lets that much time pass, frame by frame. */
class ManualFrames implements Frames {
  time = 0;
  private waiting = new Map<number, (time: number) => void>();
  private next = 1;
  request(step: (time: number) => void): number {
    this.waiting.set(this.next, step);
    return this.next++;
  }
  cancel(id: number): void {
    this.waiting.delete(id);
  }
  now(): number {
    return this.time;
  }
  get pending(): number {
    return this.waiting.size;
  }
  run(ms: number, frame = 16): void {
    for (let passed = 0; passed < ms && this.waiting.size; passed += frame) {
      this.time += frame;
      const steps = [...this.waiting.values()];
      this.waiting.clear();
      for (const step of steps) step(this.time);
    }
  }
}

function made(size: Size | null = phone): { panZoom: PanZoom; frames: ManualFrames; states: PanZoomState[] } {
  const frames = new ManualFrames();
  const states: PanZoomState[] = [];
  const panZoom = new PanZoom(photo, (state) => states.push(state), frames);
  if (size) panZoom.resize(size);
  return { panZoom, frames, states };
}

/** A small answer near the photo's top-left corner: out of a view zoomed in on the bottom-right. */
const CORNER: Box = { centre: { x: 60, y: 50 }, half: { x: 10, y: 20 } };

function zoomedOnBottomRight(panZoom: PanZoom): void {
  const t = panZoom.state.transform!;
  panZoom.set(zoomAbout(t, 4, toScreen(t, { x: 600, y: 450 }), phone, photo));
}

describe("the view's size", () => {
  it("is unknown until measured, then the photo opens", () => {
    const { panZoom } = made(null);
    expect(panZoom.now()).toBeNull();
    panZoom.resize({ width: 0, height: 300 }); // not laid out yet
    expect(panZoom.now()).toBeNull();
    panZoom.resize(phone);
    expect(panZoom.state.transform).toEqual(openingTransform(phone, photo));
    expect(panZoom.now()).toEqual({ size: phone, transform: openingTransform(phone, photo), slack: NO_INSETS, photo });
  });

  it("a landscape photo on an upright phone opens filling its height, and opens again when turned", () => {
    const { panZoom } = made(null);
    panZoom.resize(phone);
    const opened = panZoom.state.transform!;
    expect(photo.height * opened.scale).toBeCloseTo(phone.height); // the height filled
    expect(isFitted(opened, phone, photo)).toBe(false); // the whole photo is a button away
    panZoom.resize(turned); // a landscape view: the photo fits it well, whole
    expect(panZoom.state.transform).toEqual(fitTransform(turned, photo));
    panZoom.fit();
    panZoom.resize(phone); // once fitted by hand, it stays the whole photo
    expect(panZoom.state.transform).toEqual(fitTransform(phone, photo));
  });

  it("a landscape photo opens around what matters, then keeps it on screen when turned back", () => {
    const { panZoom } = made();
    const friend = { x: 600, y: 240 }; // near the right edge, out of sight around the middle
    expect(toScreen(openingTransform(phone, photo), friend).x).toBeGreaterThan(phone.width);
    panZoom.showPhoto(photo, friend);
    const opened = panZoom.state.transform!;
    expect(photo.height * opened.scale).toBeCloseTo(phone.height); // still filled to the height
    const shown = toScreen(opened, friend);
    expect(shown.x).toBeGreaterThan(0);
    expect(shown.x).toBeLessThan(phone.width);
    panZoom.resize(turned); // the whole photo
    panZoom.resize(phone); // and back, not moved by hand: around the friend again
    expect(panZoom.state.transform).toEqual(opened);
    panZoom.showPhoto(photo); // another photo, nothing marked: its middle
    expect(panZoom.state.transform).toEqual(openingTransform(phone, photo));
  });

  it("a fitted view fits again when turned; a zoomed one stays zoomed", () => {
    const { panZoom } = made();
    panZoom.resize(turned);
    expect(panZoom.state.transform).toEqual(fitTransform(turned, photo));
    panZoom.set(zoomAbout(panZoom.state.transform!, 3, { x: 280, y: 206 }, turned, photo));
    const zoomed = panZoom.state.transform!.scale;
    panZoom.resize(phone);
    expect(panZoom.state.transform!.scale).toBeCloseTo(zoomed);
    expect(isFitted(panZoom.state.transform!, phone, photo)).toBe(false);
  });

  it("a new photo is shown whole", () => {
    const { panZoom } = made();
    zoomedOnBottomRight(panZoom);
    const portrait = { width: 480, height: 640 };
    panZoom.showPhoto(portrait);
    expect(panZoom.state.transform).toEqual(fitTransform(phone, portrait));
  });

  it("the whole-photo button fits the photo again", () => {
    const { panZoom } = made();
    zoomedOnBottomRight(panZoom);
    panZoom.fit();
    expect(panZoom.state.transform).toEqual(fitTransform(phone, photo));
  });
});

describe("re-checking a landmark", () => {
  it("zooms in on it, at least a few times the whole photo, and centres it", () => {
    const { panZoom } = made();
    const landmark = { x: 320, y: 240 };
    panZoom.focus(landmark);
    const t = panZoom.state.transform!;
    expect(t.scale).toBeCloseTo(fitTransform(phone, photo).scale * FOCUS_ZOOM);
    const at = toScreen(t, landmark);
    expect(at.x).toBeCloseTo(phone.width / 2);
    expect(at.y).toBeCloseTo(phone.height / 2);
  });
});

describe("bringing the answer into view", () => {
  it("brings it out again from under a band that grew, or after the phone turned", () => {
    const { panZoom, frames } = made();
    const top: Box = { centre: { x: 320, y: 30 }, half: { x: 20, y: 20 } };
    panZoom.answer(top, false);
    frames.run(GLIDE_MS);
    expect(boxInView(top, panZoom.state.transform!, phone, NO_INSETS)).toBe(true);
    // The status grows over the photo's top (a warning came): the view moves down.
    const status = { top: 200, right: 12, bottom: 12, left: 12 };
    panZoom.setInsets(status);
    frames.run(GLIDE_MS);
    expect(boxInView(top, panZoom.state.transform!, phone, status)).toBe(true);
    // The phone turned: the view is measured again, and the answer is still clear.
    panZoom.resize(turned);
    frames.run(GLIDE_MS);
    expect(boxInView(top, panZoom.state.transform!, turned, status)).toBe(true);
  });

  it("glides to it, published as gliding until the glide ends", () => {
    const { panZoom, frames } = made();
    zoomedOnBottomRight(panZoom);
    const from = panZoom.state.transform!;
    expect(boxInView(CORNER, from, phone, NO_INSETS)).toBe(false);
    panZoom.answer(CORNER, false);
    expect(panZoom.state.gliding).toBe(true);
    frames.run(GLIDE_MS / 2);
    const halfway = panZoom.state.transform!;
    expect(halfway).not.toEqual(from);
    expect(panZoom.state.gliding).toBe(true);
    frames.run(GLIDE_MS);
    expect(panZoom.state.gliding).toBe(false);
    expect(frames.pending).toBe(0);
    expect(panZoom.state.transform).toEqual(frameTarget(CORNER, from, phone, photo, NO_INSETS));
    expect(boxInView(CORNER, panZoom.state.transform!, phone, NO_INSETS)).toBe(true);
  });

  it("jumps to it at once when the person asked for less motion", () => {
    const { panZoom, frames, states } = made();
    panZoom.reducedMotion = true;
    zoomedOnBottomRight(panZoom);
    const from = panZoom.state.transform!;
    const before = states.length;
    panZoom.answer(CORNER, false);
    expect(frames.pending).toBe(0);
    expect(states.slice(before).some((state) => state.gliding)).toBe(false);
    expect(panZoom.state.transform).toEqual(frameTarget(CORNER, from, phone, photo, NO_INSETS));
  });

  it("waits for the gesture in progress to end", () => {
    const { panZoom, frames } = made();
    zoomedOnBottomRight(panZoom);
    const during = panZoom.state.transform;
    panZoom.answer(CORNER, true);
    frames.run(GLIDE_MS * 2);
    expect(panZoom.state.transform).toEqual(during);
    panZoom.gestureEnded();
    // ...and keeps still a moment more: the finger may be about to tap again.
    frames.run(QUIET_MS / 2);
    expect(panZoom.state.transform).toEqual(during);
    panZoom.gestureStarted(); // it does: the wait starts again when it lifts
    panZoom.gestureEnded();
    frames.run(QUIET_MS * 0.9);
    expect(panZoom.state.transform).toEqual(during);
    frames.run(QUIET_MS / 2 + GLIDE_MS * 2);
    expect(boxInView(CORNER, panZoom.state.transform!, phone, NO_INSETS)).toBe(true);
  });

  it("does not move for a refinement inside the answer's frame", () => {
    const { panZoom, frames } = made();
    zoomedOnBottomRight(panZoom);
    panZoom.answer(CORNER, false);
    frames.run(GLIDE_MS * 2);
    zoomedOnBottomRight(panZoom);
    const away = panZoom.state.transform;
    panZoom.answer({ ...CORNER, centre: { x: 65, y: 55 } }, false);
    expect(panZoom.state.gliding).toBe(false);
    expect(panZoom.state.transform).toEqual(away);
  });

  it("stops where it is when a finger lands", () => {
    const { panZoom, frames } = made();
    zoomedOnBottomRight(panZoom);
    panZoom.answer(CORNER, false);
    frames.run(GLIDE_MS / 3);
    const stopped = panZoom.state.transform;
    panZoom.stopGlide();
    frames.run(GLIDE_MS);
    expect(panZoom.state.gliding).toBe(false);
    expect(panZoom.state.transform).toEqual(stopped);
  });

  it("waits for the view to be measured", () => {
    const { panZoom, frames } = made(null);
    panZoom.answer(CORNER, false);
    panZoom.resize(phone);
    expect(panZoom.state.gliding).toBe(false);
    panZoom.answer(CORNER, false); // the view's hook asks again once measured
    frames.run(GLIDE_MS * 2);
    expect(boxInView(CORNER, panZoom.state.transform!, phone, NO_INSETS)).toBe(true);
  });
});
