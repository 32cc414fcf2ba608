import { describe, expect, it } from "vitest";
import { boxInView, clipToPhoto, easeInOut, edgeArrow, frameTarget, glide, movedNoticeably, type Box } from "./reframe";
import { centreOn, fitTransform, toScreen } from "./viewTransform";

const VIEW = { width: 400, height: 600 };
const PHOTO = { width: 640, height: 480 };
const NONE = { top: 0, right: 0, bottom: 0, left: 0 };
const BOX: Box = { centre: { x: 600, y: 60 }, half: { x: 15, y: 15 } };

describe("bringing the answer into view", () => {
  it("leaves a view that already shows it", () => {
    expect(frameTarget(BOX, fitTransform(VIEW, PHOTO), VIEW, PHOTO, NONE)).toBeNull();
  });

  it("moves a view zoomed in elsewhere so that the answer is in sight, with room around it", () => {
    const zoomed = centreOn({ x: 100, y: 400 }, 3, VIEW, PHOTO);
    expect(boxInView(BOX, zoomed, VIEW, NONE)).toBe(false);
    const target = frameTarget(BOX, zoomed, VIEW, PHOTO, NONE);
    expect(target).not.toBeNull();
    if (!target) return;
    expect(boxInView(BOX, target, VIEW, NONE)).toBe(true);
    expect(target.scale).toBeLessThanOrEqual(3); // never zooms in further
    expect(target.scale).toBeGreaterThanOrEqual(fitTransform(VIEW, PHOTO).scale);
  });

  it("keeps the answer out from under the status", () => {
    const insets = { top: 250, right: 0, bottom: 0, left: 0 };
    const box: Box = { centre: { x: 320, y: 150 }, half: { x: 15, y: 15 } };
    const fitted = fitTransform(VIEW, PHOTO); // the photo's top is at y = 150: under the status
    expect(toScreen(fitted, box.centre).y - 15 * fitted.scale).toBeLessThan(250);
    const target = frameTarget(box, fitted, VIEW, PHOTO, insets);
    expect(target).not.toBeNull();
    if (target) expect(toScreen(target, box.centre).y - 15 * target.scale).toBeGreaterThan(250);
  });

  it("moves a photo as tall as the view down from under the status to show its very top", () => {
    // A portrait photo, fitted: its top is the view's top, and zooming in alone would
    // never bring a box at its top edge below the status.
    const portrait = { width: 300, height: 600 };
    const insets = { top: 120, right: 12, bottom: 12, left: 12 };
    const top: Box = { centre: { x: 150, y: 40 }, half: { x: 20, y: 30 } };
    const fitted = fitTransform(VIEW, portrait);
    expect(fitted.ty).toBe(0);
    const target = frameTarget(top, fitted, VIEW, portrait, insets);
    expect(target).not.toBeNull();
    if (!target) return;
    expect(boxInView(top, target, VIEW, insets)).toBe(true);
    expect(target.scale).toBeCloseTo(fitted.scale); // moved, not zoomed
    expect(target.ty).toBeLessThanOrEqual(insets.top); // the photo's edge no further in than the band
  });

  it("aims at the nearest border point of an answer outside the photo", () => {
    const clipped = clipToPhoto({ centre: { x: 900, y: 100 }, half: { x: 10, y: 10 } }, PHOTO);
    expect(clipped.centre).toEqual({ x: 640, y: 100 });
  });

  it("reframes for a new answer or one that moved out of its frame, not for a refinement", () => {
    expect(movedNoticeably(null, BOX)).toBe(true);
    expect(movedNoticeably(BOX, { ...BOX, centre: { x: 605, y: 62 } })).toBe(false);
    expect(movedNoticeably(BOX, { ...BOX, centre: { x: 630, y: 60 } })).toBe(true);
  });

  it("glides from one view to the other", () => {
    const from = fitTransform(VIEW, PHOTO);
    const to = centreOn({ x: 600, y: 60 }, 2, VIEW, PHOTO);
    expect(glide(from, to, 0, VIEW)).toEqual(from);
    const end = glide(from, to, 1, VIEW);
    expect(end.scale).toBeCloseTo(to.scale);
    expect(end.tx).toBeCloseTo(to.tx);
    expect(end.ty).toBeCloseTo(to.ty);
    expect(easeInOut(0)).toBe(0);
    expect(easeInOut(2)).toBe(1);
  });
});

describe("the arrow to an answer out of sight", () => {
  it("points from the middle towards a target outside, on the box's border", () => {
    const box = { left: 0, top: 0, right: 400, bottom: 300 };
    expect(edgeArrow({ x: 200, y: 150 }, box, 20)).toBeNull();
    const arrow = edgeArrow({ x: 1000, y: 150 }, box, 20);
    expect(arrow?.at).toEqual({ x: 380, y: 150 });
    expect(arrow?.angle).toBeCloseTo(0);
    expect(edgeArrow({ x: 200, y: -500 }, box, 20)?.at.y).toBeCloseTo(20);
  });
});
