import { describe, expect, it } from "vitest";
import { MIN_FRAME_CSS, answerFrame, conicPoints, edgeArrow, insideEllipse, personSize, screenFrame } from "./answerLayer";

const PHOTO = { width: 640, height: 480 };

describe("the answer's frame", () => {
  it("is never smaller than a person far across a hall, and says 'friend?' without a region", () => {
    const frame = answerFrame({ x: 100, y: 100 }, null, PHOTO);
    expect(personSize(PHOTO)).toBeCloseTo(800 / 55);
    expect(frame.half).toEqual({ x: personSize(PHOTO), y: personSize(PHOTO) });
    expect(frame.sure).toBe(false);
    expect(frame.outlined).toBe(false);
  });

  it("holds the whole 95 % region, outlined when it is larger than a person", () => {
    const region = { center: [300, 200] as [number, number], axes: [60, 12] as [number, number], angle_deg: 90 };
    const frame = answerFrame({ x: 300, y: 200 }, region, PHOTO);
    expect(frame.half.y).toBeGreaterThanOrEqual(60);
    expect(frame.half.x).toBeGreaterThanOrEqual(personSize(PHOTO));
    expect(frame.outlined).toBe(true);
    const small = answerFrame({ x: 300, y: 200 }, { ...region, axes: [3, 2] }, PHOTO);
    expect(small.outlined).toBe(false); // inside the brackets: its outline would cover the friend
    const thin = answerFrame({ x: 300, y: 200 }, { ...region, axes: [60, 3] }, PHOTO);
    expect(thin.outlined).toBe(false); // its outline would cross a person standing in it
    expect(insideEllipse({ x: 300, y: 255 }, region)).toBe(true);
    expect(insideEllipse({ x: 320, y: 200 }, region)).toBe(false);
  });

  it("keeps a least size on the screen when zoomed out far", () => {
    const frame = answerFrame({ x: 100, y: 100 }, null, PHOTO);
    const { half } = screenFrame(frame, { scale: 0.1, tx: 0, ty: 0 });
    expect(half.x).toBe(MIN_FRAME_CSS);
    expect(screenFrame(frame, { scale: 4, tx: 0, ty: 0 }).half.x).toBeCloseTo(4 * personSize(PHOTO));
  });
});

describe("the curve and the arrows", () => {
  it("finds a circle's points where it crosses the photo's rows and columns", () => {
    // (x - 320)^2 + (y - 240)^2 = 100^2
    const conic = [
      [1, 0, -320],
      [0, 1, -240],
      [-320, -240, 320 * 320 + 240 * 240 - 100 * 100],
    ];
    const points = conicPoints(conic, PHOTO, 4);
    expect(points.length).toBeGreaterThan(50);
    for (const p of points) expect(Math.hypot(p.x - 320, p.y - 240)).toBeCloseTo(100, 6);
  });

  it("points from the middle towards a target outside, on the box's border", () => {
    const box = { left: 0, top: 0, right: 400, bottom: 300 };
    expect(edgeArrow({ x: 200, y: 150 }, box, 20)).toBeNull();
    const arrow = edgeArrow({ x: 1000, y: 150 }, box, 20);
    expect(arrow?.at).toEqual({ x: 380, y: 150 });
    expect(arrow?.angle).toBeCloseTo(0);
    expect(edgeArrow({ x: 200, y: -500 }, box, 20)?.at.y).toBeCloseTo(20);
  });
});
