import { describe, expect, it } from "vitest";
import { LOUPE_AIM_MS, loupeTarget, type Gesture, type Grab, type Outcome } from "./gestures";
import { PointerGestures, listen, type GestureHost, type PointerInput, type ViewNow } from "./pointers";
import { NO_INSETS, fitTransform, zoomAbout, type Point, type ViewTransform } from "./viewTransform";

const size = { width: 412, height: 560 };
const photo = { width: 640, height: 480 };
/** Where the view's top-left corner is on the page (client px). */
const ORIGIN = { x: 10, y: 100 };
/** The label element of landmark 3, which the fake host grabs at screen (90, 216). */
const LABEL = new EventTarget();

/** A photo view that records what the gestures tell it. */
class View implements GestureHost {
  transform: ViewTransform;
  gestures: Gesture[] = [];
  outcomes: Outcome[] = [];
  calls: string[] = [];

  constructor(transform: ViewTransform = fitTransform(size, photo)) {
    this.transform = transform;
  }
  now(): ViewNow {
    return { transform: this.transform, size, photo, slack: NO_INSETS };
  }
  origin(): Point {
    return ORIGIN;
  }
  grabAt(target: EventTarget | null): Grab | null {
    return target === LABEL ? { id: 3, from: { x: 90, y: 216 } } : null;
  }
  transformed(transform: ViewTransform): void {
    this.transform = transform;
  }
  changed(gesture: Gesture): void {
    this.gestures.push(gesture);
  }
  finished(outcome: Outcome): void {
    this.outcomes.push(outcome);
  }
  started(): void {
    this.calls.push("started");
  }
  ended(): void {
    this.calls.push("ended");
  }
  get gesture(): Gesture | undefined {
    return this.gestures.at(-1);
  }
}

/** A pointer event at view point (x, y) (the client point is that plus ORIGIN). */
function pointer(id: number, x: number, y: number, more: Partial<PointerInput> = {}): PointerInput {
  return {
    pointerId: id,
    pointerType: "touch",
    isPrimary: id === 1,
    button: 0,
    clientX: ORIGIN.x + x,
    clientY: ORIGIN.y + y,
    timeStamp: 0,
    target: null,
    ...more,
  };
}

/** A fresh view (at fit unless given its transform), and the pointer gestures that drive it. */
function touched(transform?: ViewTransform): { view: View; gestures: PointerGestures } {
  const view = new View(transform);
  return { view, gestures: new PointerGestures(view) };
}

describe("a finger", () => {
  it("a tap places the mark where the finger lifted, relative to the view", () => {
    const { view, gestures } = touched();
    expect(gestures.down(pointer(1, 100, 200))).toBe(true);
    expect(gestures.active).toBe(true);
    expect(view.gesture && loupeTarget(view.gesture)).toEqual({ x: 100, y: 200 }); // the loupe
    expect(gestures.up(pointer(1, 100, 200))).toBe(true);
    expect(view.outcomes).toEqual([{ kind: "place", at: { x: 100, y: 200 }, aim: "finger" }]);
    expect(view.calls).toEqual(["started", "ended"]);
    expect(gestures.active).toBe(false);
  });

  it("held long enough, it aimed with the loupe", () => {
    const { view, gestures } = touched();
    gestures.down(pointer(1, 100, 200, { timeStamp: 1000 }));
    gestures.up(pointer(1, 100, 200, { timeStamp: 1000 + LOUPE_AIM_MS }));
    expect(view.outcomes).toEqual([{ kind: "place", at: { x: 100, y: 200 }, aim: "loupe" }]);
  });

  it("dragging a landmark's label moves the landmark; the lift point counts", () => {
    const { view, gestures } = touched();
    gestures.down(pointer(1, 110, 196, { target: LABEL }));
    gestures.move(pointer(1, 115, 200));
    gestures.up(pointer(1, 120, 206));
    expect(view.outcomes).toEqual([{ kind: "move", id: 3, to: { x: 100, y: 226 }, aim: "loupe" }]);
  });

  it("a touch the system cancels places nothing", () => {
    const { view, gestures } = touched();
    gestures.down(pointer(1, 100, 200));
    gestures.up(pointer(1, 100, 200), true);
    expect(view.outcomes).toEqual([]);
    expect(view.calls).toEqual(["started", "ended"]);
  });

  it("a finger whose lift never came is dropped when the next first finger lands", () => {
    const { view, gestures } = touched();
    gestures.down(pointer(1, 100, 200));
    // No pointerup for finger 1; finger 7 lands as the only one (primary): a tap, not a pinch.
    gestures.down(pointer(7, 300, 300, { isPrimary: true }));
    gestures.up(pointer(7, 300, 300));
    expect(view.outcomes).toEqual([{ kind: "place", at: { x: 300, y: 300 }, aim: "finger" }]);
  });

  it("moves and lifts of pointers that are not down are not the view's", () => {
    const { view, gestures } = touched();
    expect(gestures.move(pointer(4, 10, 10, { pointerType: "mouse" }))).toBe(false); // a hover
    expect(gestures.up(pointer(4, 10, 10))).toBe(false);
    expect(gestures.down(pointer(4, 10, 10, { pointerType: "mouse", button: 2 }))).toBe(false);
    expect(view.gestures).toEqual([]);
  });
});

describe("two fingers", () => {
  it("spreading zooms about their midpoint and places nothing, whichever lifts first", () => {
    const { view, gestures } = touched();
    const fitted = view.transform;
    gestures.down(pointer(1, 190, 290));
    gestures.down(pointer(2, 210, 310));
    expect(view.gesture?.kind).toBe("pinch");
    gestures.move(pointer(1, 175, 275));
    gestures.move(pointer(2, 225, 325));
    expect(view.transform.scale).toBeCloseTo(fitted.scale * 2.5);
    // The photo point under the fingers' midpoint stays under it.
    const mid = { x: (200 - fitted.tx) / fitted.scale, y: (300 - fitted.ty) / fitted.scale };
    expect(view.transform.tx + mid.x * view.transform.scale).toBeCloseTo(200);
    gestures.up(pointer(1, 175, 275));
    gestures.up(pointer(2, 225, 325));
    expect(view.outcomes).toEqual([]);
    expect(view.calls).toEqual(["started", "ended"]);
  });
  it("a pinch the system cancels leaves the view where the fingers had it", () => {
    const { view, gestures } = touched();
    gestures.down(pointer(1, 190, 290));
    gestures.down(pointer(2, 210, 310));
    gestures.move(pointer(2, 250, 350));
    const pinched = view.transform;
    // Some browsers send a cancel at the page's corner, not where the finger was.
    gestures.up({ ...pointer(2, 0, 0), clientX: 0, clientY: 0 }, true);
    gestures.up({ ...pointer(1, 0, 0), clientX: 0, clientY: 0 }, true);
    expect(view.transform).toEqual(pinched);
    expect(view.outcomes).toEqual([]);
  });
});

describe("a mouse", () => {
  it("a click places, aimed as with the loupe, and shows no loupe", () => {
    const { view, gestures } = touched();
    gestures.down(pointer(1, 50, 250, { pointerType: "mouse" }));
    expect(view.gesture && loupeTarget(view.gesture)).toBeNull();
    gestures.up(pointer(1, 50, 250, { pointerType: "mouse" }));
    expect(view.outcomes).toEqual([{ kind: "place", at: { x: 50, y: 250 }, aim: "loupe" }]);
  });

  it("a drag pans a zoomed photo and places nothing", () => {
    const zoomed = zoomAbout(fitTransform(size, photo), 3, { x: 200, y: 280 }, size, photo);
    const { view, gestures } = touched(zoomed);
    const mouse = { pointerType: "mouse" };
    gestures.down(pointer(1, 200, 280, mouse));
    gestures.move(pointer(1, 180, 270, mouse));
    expect(view.transform.tx).toBeCloseTo(zoomed.tx - 20);
    expect(view.transform.ty).toBeCloseTo(zoomed.ty - 10);
    gestures.up(pointer(1, 180, 270, mouse));
    expect(view.outcomes).toEqual([]);
  });

  it("the wheel zooms about the pointer and stops a glide", () => {
    const { view, gestures } = touched();
    const before = view.transform;
    gestures.wheel({ clientX: ORIGIN.x + 206, clientY: ORIGIN.y + 280, deltaY: -100, deltaMode: 0 });
    expect(view.transform.scale).toBeCloseTo(before.scale * Math.exp(0.2));
    expect(view.calls).toEqual(["started"]);
  });
});

describe("listening", () => {
  /** A DOM-like event: what a PointerEvent carries beyond an Event's own fields. */
  function event(type: string, fields: Partial<PointerInput> & { deltaY?: number; deltaMode?: number }): Event {
    return Object.assign(new Event(type, { cancelable: true }), fields);
  }

  it("takes pointers down on the view and their moves and lifts anywhere, then stops", () => {
    const element = new EventTarget();
    const scope = new EventTarget();
    const view = new View();
    const stop = listen(element, scope, new PointerGestures(view));
    const at = (x: number, y: number) => ({ pointerId: 1, pointerType: "touch", isPrimary: true, button: 0, clientX: ORIGIN.x + x, clientY: ORIGIN.y + y });

    const down = event("pointerdown", at(100, 200));
    element.dispatchEvent(down);
    expect(down.defaultPrevented).toBe(true); // no text selection, no imitated mouse
    scope.dispatchEvent(event("pointermove", at(130, 180)));
    const up = event("pointerup", at(130, 180));
    scope.dispatchEvent(up);
    expect(up.defaultPrevented).toBe(true);
    expect(view.outcomes).toEqual([{ kind: "place", at: { x: 130, y: 180 }, aim: "loupe" }]);

    // A hover elsewhere on the page is left alone.
    const hover = event("pointermove", { ...at(5, 5), pointerType: "mouse" });
    scope.dispatchEvent(hover);
    expect(hover.defaultPrevented).toBe(false);

    element.dispatchEvent(event("wheel", { ...at(206, 280), deltaY: -100, deltaMode: 0 }));
    const zoomed = view.transform.scale;
    stop();
    element.dispatchEvent(event("wheel", { ...at(206, 280), deltaY: -100, deltaMode: 0 }));
    element.dispatchEvent(event("pointerdown", at(100, 200)));
    scope.dispatchEvent(event("pointerup", at(100, 200)));
    expect(view.transform.scale).toBe(zoomed);
    expect(view.outcomes).toHaveLength(1);
  });

  it("a cancelled pointer places nothing", () => {
    const element = new EventTarget();
    const scope = new EventTarget();
    const view = new View();
    listen(element, scope, new PointerGestures(view));
    const at = { pointerId: 1, pointerType: "touch", isPrimary: true, button: 0, clientX: 50, clientY: 150 };
    element.dispatchEvent(event("pointerdown", at));
    scope.dispatchEvent(event("pointercancel", at));
    expect(view.outcomes).toEqual([]);
    expect(view.calls).toEqual(["started", "ended"]);
  });
});
