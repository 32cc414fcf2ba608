import { describe, expect, it } from "vitest";
import {
  IDLE,
  LOUPE_AIM_MS,
  editOf,
  fingerDown,
  fingerUp,
  fingersMove,
  loupeTarget,
  wheelFactor,
  type Gesture,
} from "./gestures";
import { tapSigma } from "./precision";
import { fitTransform, zoomAbout, type Point } from "./viewTransform";

const view = { width: 412, height: 560 };
const photo = { width: 640, height: 480 };
const fitted = fitTransform(view, photo);

function fingers(...points: Array<[number, Point]>): Map<number, Point> {
  return new Map(points);
}

describe("one finger", () => {
  it("a tap places the mark where the finger was", () => {
    const down = fingerDown(IDLE, fingers([1, { x: 100, y: 200 }]), 1, null, fitted);
    expect(loupeTarget(down)).toEqual({ x: 100, y: 200 });
    const { gesture, outcome } = fingerUp(down, fingers(), 1);
    expect(outcome).toEqual({ kind: "place", at: { x: 100, y: 200 }, aim: "finger" });
    expect(gesture).toEqual(IDLE);
  });

  it("a finger held still long enough aimed with the loupe", () => {
    const down = fingerDown(IDLE, fingers([1, { x: 100, y: 200 }]), 1, null, fitted, false, 1000);
    const quick = fingerUp(down, fingers(), 1, false, 1000 + LOUPE_AIM_MS - 1).outcome;
    const held = fingerUp(down, fingers(), 1, false, 1000 + LOUPE_AIM_MS).outcome;
    expect(quick).toMatchObject({ kind: "place", aim: "finger" });
    expect(held).toMatchObject({ kind: "place", aim: "loupe" });
  });

  it("dragging adjusts, and the release point is placed", () => {
    let gesture: Gesture = fingerDown(IDLE, fingers([1, { x: 100, y: 200 }]), 1, null, fitted);
    const moved = fingersMove(gesture, fingers([1, { x: 130, y: 180 }]), fitted, view, photo, false);
    gesture = moved.gesture;
    expect(moved.transform).toBeNull(); // one finger never pans or zooms
    expect(loupeTarget(gesture)).toEqual({ x: 130, y: 180 });
    // Slid under the loupe: aimed with it, however quick.
    expect(fingerUp(gesture, fingers(), 1).outcome).toEqual({ kind: "place", at: { x: 130, y: 180 }, aim: "loupe" });
  });

  it("a press on a label grabs that landmark: dragging moves it from where it was", () => {
    const grab = { id: 3, from: { x: 90, y: 216 } };
    let gesture: Gesture = fingerDown(IDLE, fingers([1, { x: 110, y: 196 }]), 1, grab, fitted);
    gesture = fingersMove(gesture, fingers([1, { x: 120, y: 206 }]), fitted, view, photo, false).gesture;
    expect(loupeTarget(gesture)).toEqual({ x: 100, y: 226 });
    expect(fingerUp(gesture, fingers(), 1).outcome).toEqual({ kind: "move", id: 3, to: { x: 100, y: 226 }, aim: "loupe" });
  });

  it("a tap on a label selects that landmark", () => {
    const grab = { id: 3, from: { x: 90, y: 216 } };
    let gesture: Gesture = fingerDown(IDLE, fingers([1, { x: 110, y: 196 }]), 1, grab, fitted);
    gesture = fingersMove(gesture, fingers([1, { x: 112, y: 197 }]), fitted, view, photo, false).gesture;
    expect(fingerUp(gesture, fingers(), 1).outcome).toEqual({ kind: "select", id: 3 });
  });

  it("a cancelled touch places nothing", () => {
    const down = fingerDown(IDLE, fingers([1, { x: 100, y: 200 }]), 1, null, fitted);
    expect(fingerUp(down, fingers(), 1, true).outcome).toEqual({ kind: "none" });
  });
});

describe("two fingers", () => {
  it("pinching out zooms about their midpoint and places nothing", () => {
    let gesture: Gesture = fingerDown(IDLE, fingers([1, { x: 190, y: 290 }]), 1, null, fitted);
    const both = fingers([1, { x: 190, y: 290 }], [2, { x: 210, y: 310 }]);
    gesture = fingerDown(gesture, both, 2, null, fitted);
    expect(gesture.kind).toBe("pinch");
    expect(loupeTarget(gesture)).toBeNull();
    const spread = fingers([1, { x: 175, y: 275 }], [2, { x: 225, y: 325 }]);
    const { transform } = fingersMove(gesture, spread, fitted, view, photo, false);
    expect(transform?.scale).toBeCloseTo(fitted.scale * 2.5);
    // Lifting one finger, then the other: still nothing placed.
    const first = fingerUp(gesture, fingers([2, { x: 225, y: 325 }]), 1);
    expect(first.outcome.kind).toBe("none");
    expect(first.gesture.kind).toBe("done");
    const still = fingerDown(first.gesture, fingers([2, { x: 225, y: 325 }]), 2, null, fitted);
    expect(still.kind).toBe("done");
    const last = fingerUp(first.gesture, fingers(), 2);
    expect(last.outcome.kind).toBe("none");
    expect(last.gesture).toEqual(IDLE);
  });

  it("both fingers down at once start a pinch", () => {
    const both = fingers([5, { x: 100, y: 100 }], [6, { x: 200, y: 200 }]);
    expect(fingerDown(IDLE, both, 5, null, fitted).kind).toBe("pinch");
  });
});

describe("the mouse", () => {
  it("a click places", () => {
    const down = fingerDown(IDLE, fingers([0, { x: 50, y: 250 }]), 0, null, fitted, true);
    expect(loupeTarget(down)).toBeNull(); // the pointer is precise: no loupe
    // Its pointer is as precise as the loupe.
    expect(fingerUp(down, fingers(), 0).outcome).toEqual({ kind: "place", at: { x: 50, y: 250 }, aim: "loupe" });
  });

  it("a drag pans a zoomed photo and places nothing", () => {
    const zoomed = zoomAbout(fitted, 3, { x: 200, y: 280 }, view, photo);
    let gesture: Gesture = fingerDown(IDLE, fingers([0, { x: 200, y: 280 }]), 0, null, zoomed, true);
    const first = fingersMove(gesture, fingers([0, { x: 180, y: 270 }]), zoomed, view, photo, true);
    gesture = first.gesture;
    expect(gesture.kind).toBe("pan");
    expect(first.transform?.tx).toBeCloseTo(zoomed.tx - 20);
    expect(first.transform?.ty).toBeCloseTo(zoomed.ty - 10);
    expect(fingerUp(gesture, fingers(), 0).outcome.kind).toBe("none");
  });

  it("the wheel zooms in when turned up and out when turned down", () => {
    expect(wheelFactor(-100)).toBeGreaterThan(1);
    expect(wheelFactor(100)).toBeLessThan(1);
    expect(wheelFactor(-100) * wheelFactor(100)).toBeCloseTo(1);
  });
});

describe("what a lift does to the marks", () => {
  const zoomed = zoomAbout(fitted, 2, { x: 0, y: 0 }, view, photo);

  it("a tap is placed in photo px with its precision at the zoom it was made at", () => {
    const at = { x: fitted.tx + 100 * fitted.scale, y: fitted.ty + 50 * fitted.scale };
    const edit = editOf({ kind: "place", at, aim: "finger" }, fitted, photo);
    expect(edit?.kind).toBe("place");
    const tap = edit?.kind === "place" ? edit.tap : null;
    expect(tap?.x).toBeCloseTo(100);
    expect(tap?.y).toBeCloseTo(50);
    expect(tap?.sigma).toBe(tapSigma(fitted.scale, "finger"));
    const closer = editOf({ kind: "place", at, aim: "finger" }, zoomed, photo);
    expect(closer?.kind === "place" && closer.tap.sigma).toBeLessThan(tap?.sigma ?? 0);
  });

  it("a tap beside the photo places nothing", () => {
    const above = { x: 100, y: fitted.ty - 5 };
    expect(editOf({ kind: "place", at: above, aim: "finger" }, fitted, photo)).toBeNull();
  });

  it("a landmark dragged off the photo stays on its edge", () => {
    const edit = editOf({ kind: "move", id: 2, to: { x: -50, y: 9999 }, aim: "loupe" }, fitted, photo);
    expect(edit).toMatchObject({ kind: "move", id: 2, tap: { x: 0, y: photo.height } });
  });

  it("a tap on a label selects it; nothing does nothing", () => {
    expect(editOf({ kind: "select", id: 4 }, fitted, photo)).toEqual({ kind: "select", id: 4 });
    expect(editOf({ kind: "none" }, fitted, photo)).toBeNull();
  });
});
