import { describe, expect, it } from "vitest";
import {
  centreOn,
  clampTransform,
  fitTransform,
  isFitted,
  isInsidePhoto,
  openingTransform,
  panBy,
  pinchTransform,
  scaleLimits,
  toPhoto,
  toScreen,
  zoomAbout,
  type Point,
} from "./viewTransform";

const phone = { width: 412, height: 560 };
const photo = { width: 640, height: 480 };
const fitted = fitTransform(phone, photo);
/** Zoomed in 4 times about a point left of the view's middle. */
const zoomed = zoomAbout(fitted, 4, { x: 200, y: 280 }, phone, photo);

function near(a: Point, b: Point, digits = 6): void {
  expect(a.x).toBeCloseTo(b.x, digits);
  expect(a.y).toBeCloseTo(b.y, digits);
}

/** Two fingers on the screen, at (x1, y1) and (x2, y2). */
function fingers(x1: number, y1: number, x2: number, y2: number): readonly [Point, Point] {
  return [
    { x: x1, y: y1 },
    { x: x2, y: y2 },
  ];
}

describe("the fitted photo", () => {
  it("fills the width of a portrait phone and is centred vertically", () => {
    expect(fitted.scale).toBeCloseTo(412 / 640);
    expect(fitted.tx).toBeCloseTo(0);
    expect(fitted.ty).toBeCloseTo((560 - 480 * fitted.scale) / 2);
    near(toScreen(fitted, { x: 320, y: 240 }), { x: 206, y: 280 });
  });

  it("fills the height of a wide view and is centred horizontally", () => {
    const t = fitTransform({ width: 1000, height: 300 }, photo);
    expect(t.scale).toBeCloseTo(300 / 480);
    expect(t.ty).toBeCloseTo(0);
    expect(t.tx).toBeCloseTo((1000 - 640 * t.scale) / 2);
  });

  it("opens fitted when that fills most of the view, else filling it around the middle", () => {
    const portrait = { width: 480, height: 640 };
    expect(openingTransform(phone, portrait)).toEqual(fitTransform(phone, portrait));
    const wide = openingTransform(phone, photo); // 4:3 on an upright phone: 55 % fitted
    expect(photo.height * wide.scale).toBeCloseTo(phone.height);
    near(toScreen(wide, { x: 320, y: 240 }), { x: phone.width / 2, y: phone.height / 2 });
    const aside = openingTransform(phone, photo, { x: 600, y: 240 }); // around a point: clamped
    expect(aside.tx).toBeCloseTo(phone.width - photo.width * aside.scale);
    const turned = { width: 560, height: 412 };
    expect(openingTransform(turned, photo)).toEqual(fitTransform(turned, photo));
  });

  it("counts as fitted, and a zoomed view does not", () => {
    expect(isFitted(fitted, phone, photo)).toBe(true);
    expect(isFitted(zoomAbout(fitted, 2, { x: 200, y: 280 }, phone, photo), phone, photo)).toBe(false);
  });
});

describe("screen <-> photo", () => {
  it("round-trips any point under any zoom and pan", () => {
    const transforms = [
      fitTransform(phone, photo),
      { scale: 2.5, tx: -300, ty: -120 },
      { scale: 0.2, tx: 13.5, ty: 400 },
    ];
    for (const t of transforms) {
      for (const p of [
        { x: 0, y: 0 },
        { x: 640, y: 480 },
        { x: 123.4, y: 456.7 },
      ]) {
        near(toPhoto(t, toScreen(t, p)), p);
        near(toScreen(t, toPhoto(t, p)), p);
      }
    }
  });

  it("tells taps on the photo from taps on the margin", () => {
    expect(isInsidePhoto({ x: 0, y: 0 }, photo)).toBe(true);
    expect(isInsidePhoto({ x: 640, y: 480 }, photo)).toBe(true);
    expect(isInsidePhoto({ x: -0.5, y: 10 }, photo)).toBe(false);
    expect(isInsidePhoto({ x: 10, y: 481 }, photo)).toBe(false);
    expect(isInsidePhoto(toPhoto(fitted, { x: 200, y: 20 }), photo)).toBe(false); // black band above
  });
});

describe("zoom", () => {
  it("about a point keeps that point where it is", () => {
    const centre = { x: 180, y: 300 };
    const under = toPhoto(fitted, centre);
    const zoomed = zoomAbout(fitted, 3, centre, phone, photo);
    expect(zoomed.scale).toBeCloseTo(3 * fitted.scale);
    near(toScreen(zoomed, under), centre);
    // and zooming back out the same way returns to the fitted view
    const back = zoomAbout(zoomed, 1 / 3, centre, phone, photo);
    expect(back.scale).toBeCloseTo(fitted.scale);
  });

  it("stays between the fitted photo and the largest zoom", () => {
    const { min, max } = scaleLimits(phone, photo);
    expect(zoomAbout(fitted, 0.1, { x: 100, y: 100 }, phone, photo).scale).toBeCloseTo(min);
    expect(zoomAbout(fitted, 1000, { x: 100, y: 100 }, phone, photo).scale).toBeCloseTo(max);
    expect(max).toBeGreaterThanOrEqual(2);
  });

  it("pinching out grows the scale about the fingers' midpoint", () => {
    const [from, to] = [fingers(190, 290, 210, 310), fingers(175, 275, 225, 325)];
    const under = toPhoto(fitted, { x: 200, y: 300 });
    const pinched = pinchTransform(fitted, from, to, phone, photo);
    expect(pinched.scale).toBeCloseTo(fitted.scale * 2.5);
    near(toScreen(pinched, under), { x: 200, y: 300 }, 4);
  });

  it("two fingers moving together pan the zoomed photo", () => {
    const [from, to] = [fingers(150, 250, 250, 250), fingers(130, 240, 230, 240)];
    const moved = pinchTransform(zoomed, from, to, phone, photo);
    expect(moved.scale).toBeCloseTo(zoomed.scale);
    expect(moved.tx).toBeCloseTo(zoomed.tx - 20);
    expect(moved.ty).toBeCloseTo(zoomed.ty - 10);
  });
});

describe("clamping", () => {
  it("never pans the photo away from the view's edges", () => {
    const farLeft = panBy(zoomed, 10_000, 10_000, phone, photo);
    expect(farLeft.tx).toBe(0);
    expect(farLeft.ty).toBe(0);
    const farRight = panBy(zoomed, -10_000, -10_000, phone, photo);
    expect(farRight.tx).toBeCloseTo(phone.width - photo.width * zoomed.scale);
    expect(farRight.ty).toBeCloseTo(phone.height - photo.height * zoomed.scale);
  });

  it("centres an axis on which the photo is smaller than the view", () => {
    const t = clampTransform({ scale: 0.7, tx: 999, ty: -999 }, phone, photo);
    expect(t.ty).toBeCloseTo((phone.height - 480 * 0.7) / 2);
    expect(t.tx).toBeLessThanOrEqual(0);
    expect(t.tx).toBeGreaterThanOrEqual(phone.width - 640 * 0.7);
  });

  it("cannot pan the fitted photo", () => {
    const panned = panBy(fitted, 50, 50, phone, photo);
    expect(panned.tx).toBeCloseTo(fitted.tx);
    expect(panned.ty).toBeCloseTo(fitted.ty);
  });

  it("lets the photo's edge come in as far as a covered band, no further", () => {
    const bands = { top: 100, right: 0, bottom: 60, left: 0 };
    const down = panBy(zoomed, 0, 10_000, phone, photo, bands);
    expect(down.ty).toBe(100); // the photo's top at the status's bottom edge
    const up = panBy(zoomed, 0, -10_000, phone, photo, bands);
    expect(up.ty).toBeCloseTo(phone.height - 60 - photo.height * zoomed.scale);
    // Sideways there is no band: the edges stay at the view's.
    expect(panBy(zoomed, 10_000, 0, phone, photo, bands).tx).toBe(0);
    // A photo smaller than the view along an axis: centred, or moved within the band.
    const moved = panBy(fitted, 0, 500, phone, photo, { ...bands, top: 200 });
    expect(moved.ty).toBe(200);
    expect(isFitted(moved, phone, photo)).toBe(false); // not the whole photo as fitted any more
  });

  it("centres on a landmark as far as the edges allow", () => {
    const middle = centreOn({ x: 320, y: 240 }, 3, phone, photo);
    near(toScreen(middle, { x: 320, y: 240 }), { x: 206, y: 280 });
    const corner = centreOn({ x: 0, y: 0 }, 3, phone, photo);
    expect(corner.tx).toBe(0);
    expect(corner.ty).toBe(0);
  });
});
