import { describe, expect, it } from "vitest";
import {
  LABEL_CLEARANCE,
  LABEL_OFFSET,
  LOUPE_GAP,
  LOUPE_SIZE,
  labelPositions,
  loupePosition,
  loupeZoom,
} from "./markLayout";

const view = { width: 412, height: 560 };

describe("labels", () => {
  const one = (at: { x: number; y: number }, others: Array<{ x: number; y: number }> = []) =>
    labelPositions([{ id: 1, at }], view, others).get(1);

  it("sit up and right of the point, away from it", () => {
    const label = one({ x: 200, y: 200 });
    expect(label).toBeDefined();
    expect(label?.x).toBeGreaterThan(200);
    expect(label?.y).toBeLessThan(200);
    expect(Math.hypot((label?.x ?? 0) - 200, (label?.y ?? 0) - 200)).toBeGreaterThan(20);
  });

  it("flip inside the view near its edges", () => {
    const corner = one({ x: 405, y: 5 });
    expect(corner?.x).toBeLessThan(405);
    expect(corner?.y).toBeGreaterThan(5);
  });

  it("of two close landmarks do not cover each other or the other point", () => {
    const points = [
      { id: 2, at: { x: 144, y: 91 } },
      { id: 3, at: { x: 138, y: 90 } },
    ];
    const labels = labelPositions(points, view);
    const two = labels.get(2);
    const three = labels.get(3);
    expect(two && three).toBeTruthy();
    if (!two || !three) return;
    expect(Math.hypot(two.x - three.x, two.y - three.y)).toBeGreaterThanOrEqual(LABEL_CLEARANCE);
    for (const label of [two, three]) {
      for (const { at } of points) {
        expect(Math.hypot(label.x - at.x, label.y - at.y)).toBeGreaterThan(LABEL_OFFSET);
      }
    }
  });

  it("keep clear of the friend's mark", () => {
    const label = one({ x: 200, y: 200 }, [{ x: 222, y: 178 }]);
    expect(Math.hypot((label?.x ?? 0) - 222, (label?.y ?? 0) - 178)).toBeGreaterThanOrEqual(LABEL_CLEARANCE);
  });
});

describe("the loupe", () => {
  it("sits above the finger, clear of it", () => {
    const finger = { x: 200, y: 400 };
    const at = loupePosition(finger, view);
    expect(at.y + LOUPE_SIZE).toBeLessThanOrEqual(finger.y - LOUPE_GAP + 0.001);
    expect(at.x + LOUPE_SIZE / 2).toBeCloseTo(200);
  });

  it("goes beside the finger near the top, and stays in the view", () => {
    for (const finger of [
      { x: 30, y: 20 },
      { x: 400, y: 20 },
    ]) {
      const at = loupePosition(finger, view);
      expect(at.x).toBeGreaterThanOrEqual(0);
      expect(at.x + LOUPE_SIZE).toBeLessThanOrEqual(view.width);
      expect(at.y).toBeGreaterThanOrEqual(0);
      const covers = finger.x >= at.x && finger.x <= at.x + LOUPE_SIZE && finger.y >= at.y && finger.y <= at.y + LOUPE_SIZE;
      expect(covers).toBe(false);
    }
  });

  it("magnifies more than the view", () => {
    expect(loupeZoom(0.5)).toBeGreaterThan(0.5 * 2);
    expect(loupeZoom(3)).toBeGreaterThan(3);
  });
});
