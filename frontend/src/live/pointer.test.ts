import { describe, expect, it } from "vitest";
import { anchorAt, fromEuler, IDENTITY, sinceShutter } from "./orientation";
import {
  cover,
  focalFrom35mm,
  homography,
  linesToScreen,
  liveFocal,
  photoToScreen,
  pointAt,
  pointAtCurve,
  screenPerPhotoPx,
  warp,
} from "./pointer";

const DEGREE = Math.PI / 180;
const PHOTO = { width: 2560, height: 1920 };
const VIDEO = { width: 1280, height: 960 };
/** A Pixel 7's screen, portrait: the 4:3 video cropped at its sides. */
const SCREEN = { width: 412, height: 915 };
/** The photo's focal length (px), the video's, and the video on the screen. */
const f = 2000;
const fv = liveFocal(f, PHOTO, VIDEO);
const c = cover(VIDEO, SCREEN);

/** The phone upright, level, turned `alpha` (degrees; right is negative) and tilted up `up`. */
function phone(alpha: number, up = 0) {
  return { device: fromEuler(alpha, 90 + up, 0), screenAngle: 0 };
}

describe("the focal lengths", () => {
  it("reads the answer's 35 mm-equivalent as px of the photo", () => {
    // 26 mm on a 4:3 photo: its long side is about 0.75 of a 35 mm frame's diagonal...
    expect(focalFrom35mm(26, { width: 4000, height: 3000 })).toBeCloseTo((26 / Math.hypot(36, 24)) * 5000, 9);
  });

  it("scales the photo's by the long sides unless the video's was measured", () => {
    expect(liveFocal(2000, PHOTO, VIDEO)).toBeCloseTo(1000, 9);
    // A 16:9 stream of the same sensor keeps its long side, and the focal with it.
    expect(liveFocal(2000, PHOTO, { width: 1280, height: 720 })).toBeCloseTo(1000, 9);
    expect(liveFocal(2000, PHOTO, { width: 720, height: 1280 })).toBeCloseTo(1000, 9);
    expect(liveFocal(2000, PHOTO, VIDEO, 0.9)).toBeCloseTo(0.9 * 1280, 9);
  });
});

describe("the photo's drawing in the live video", () => {

  it("is the photo, scaled, while the phone has not turned", () => {
    const h = homography(IDENTITY, f, PHOTO, fv, VIDEO);
    const p = warp(h, [1000, 700, 1]);
    expect(p[0] / p[2]).toBeCloseTo(500, 9);
    expect(p[1] / p[2]).toBeCloseTo(350, 9);
  });

  it("moves the friend by the turn: left when the phone turns right", () => {
    const r = sinceShutter(anchorAt(phone(0)), phone(-5));
    const h = homography(r, f, PHOTO, fv, VIDEO);
    // The photo's centre was straight ahead; 5 degrees to the left now.
    const p = warp(h, [PHOTO.width / 2, PHOTO.height / 2, 1]);
    expect(p[0] / p[2]).toBeCloseTo(VIDEO.width / 2 - fv * Math.tan(5 * DEGREE), 6);
    expect(p[1] / p[2]).toBeCloseTo(VIDEO.height / 2, 6);
    // A point 10 degrees right of centre in the photo is 5 degrees right of it now.
    const q = warp(h, [PHOTO.width / 2 + f * Math.tan(10 * DEGREE), PHOTO.height / 2, 1]);
    expect(q[0] / q[2]).toBeCloseTo(VIDEO.width / 2 + fv * Math.tan(5 * DEGREE), 6);
  });

  it("moves the friend down the view when the phone tilts up", () => {
    const h = homography(sinceShutter(anchorAt(phone(0)), phone(0, 4)), f, PHOTO, fv, VIDEO);
    const p = warp(h, [PHOTO.width / 2, PHOTO.height / 2, 1]);
    expect(p[1] / p[2]).toBeCloseTo(VIDEO.height / 2 + fv * Math.tan(4 * DEGREE), 6);
  });
});

describe("the video on the screen (object-fit: cover)", () => {
  it("crops the 4:3 video's sides on a portrait screen", () => {
    expect(c.scale).toBeCloseTo(915 / 960, 12);
    expect(c.offset.y).toBeCloseTo(0, 12);
    expect(c.offset.x).toBeCloseTo((412 - 1280 * (915 / 960)) / 2, 12);
    // The video's centre is the screen's.
    const h = homography(IDENTITY, 1, VIDEO, 1, VIDEO);
    const centre = photoToScreen(h, c, [640, 480]);
    expect(centre?.x).toBeCloseTo(206, 9);
    expect(centre?.y).toBeCloseTo(457.5, 9);
  });
});

describe("pointing at the friend", () => {
  const ahead: [number, number, number] = [PHOTO.width / 2, PHOTO.height / 2, 1];

  function pointing(alpha: number, up = 0, friend = ahead) {
    const h = homography(sinceShutter(anchorAt(phone(0)), phone(alpha, up)), f, PHOTO, fv, VIDEO);
    return pointAt(h, c, VIDEO, friend, 30);
  }

  it("is in view, where the turn puts them", () => {
    const p = pointing(-2);
    expect(p.kind).toBe("in-view");
    expect(p.at.x).toBeCloseTo(206 - c.scale * fv * Math.tan(2 * DEGREE), 6);
  });

  it("turns left: in the video, but cropped off the screen's side", () => {
    // 12 degrees off: inside the 1280 px video (half of it is 33 degrees), off the 412 px screen.
    const p = pointing(12);
    expect(p.kind).toBe("off-view");
    if (p.kind !== "off-view") return;
    expect(p.turn).toBe("right");
    expect(p.at.x).toBeCloseTo(412 - 30, 6);
    expect(pointing(-12).kind === "off-view" && pointing(-12)).toMatchObject({ turn: "left" });
  });

  it("turns up or down", () => {
    expect(pointing(0, 40)).toMatchObject({ kind: "off-view", turn: "down" });
    expect(pointing(0, -40)).toMatchObject({ kind: "off-view", turn: "up" });
  });

  it("turns towards a friend behind the camera, never drawn there", () => {
    // Turned 150 degrees right: the friend is behind, back over the left shoulder.
    const p = pointing(-150);
    expect(p).toMatchObject({ kind: "off-view", turn: "left" });
    // A friend behind the photo's camera (w < 0 in friend_h), seen when the phone turns round.
    expect(pointing(180, 0, [-ahead[0], -ahead[1], -1])).toMatchObject({ kind: "in-view" });
  });

  it("leaves out the points of a line behind the camera", () => {
    const h = homography(sinceShutter(anchorAt(phone(0)), phone(-80)), f, PHOTO, fv, VIDEO);
    // A line across the photo from far left to far right: 80 degrees right, its left half
    // (beyond 10 degrees left of the photo's centre) is behind.
    const line = [-200000, -2000, 0, 1280, 2560, 5000].map((x) => [x, 960]);
    const pieces = linesToScreen(h, c, [line]);
    expect(pieces).toHaveLength(1);
    expect(pieces[0]).toHaveLength(3);
  });

  it("sizes the band by the view's scale", () => {
    expect(screenPerPhotoPx(c, f, fv)).toBeCloseTo((915 / 960) * 0.5, 12);
  });
});

describe("pointing at a curve with no part in view", () => {
  // The friend's level: across the whole photo, 5 degrees above its centre, a point every
  // 400 px (as the server's polylines come).
  const level = [[-400, 0, 400, 800, 1200, 1600, 2000, 2400, 2800].map((x) => [x, 960 - f * Math.tan(5 * DEGREE)])];

  function towards(alpha: number, up: number, lines = level) {
    const h = homography(sinceShutter(anchorAt(phone(0)), phone(alpha, up)), f, PHOTO, fv, VIDEO);
    return pointAtCurve(h, c, VIDEO, fv, lines, 30);
  }

  it("is none while part of the curve is on the screen", () => {
    expect(towards(0, 0)).toBeNull();
    expect(towards(-20, 3)).toBeNull();
  });

  it("turns up or down to the curve, towards its nearest part", () => {
    // Tilted down 30 degrees: the level is 35 degrees up, off the screen's top.
    const up = towards(0, -30);
    expect(up).toMatchObject({ kind: "off-view", turn: "up" });
    // Its nearest part is straight above: the arrow near the screen's vertical centre line
    // (the nearest of the points tried, 50 photo px apart here: 0.6 degrees).
    expect(Math.abs((up?.at.x ?? 0) - SCREEN.width / 2)).toBeLessThan(10);
    expect(up?.at.y).toBeCloseTo(30, 6);
    expect(towards(10, 40)).toMatchObject({ kind: "off-view", turn: "down" });
  });

  it("turns left or right to a curve that ends", () => {
    // The level reaches 36 degrees either side of the photo's centre (f 2000, x from -400
    // to 2800): turned 70 degrees right, its nearest part (its right end) is on the left.
    expect(towards(-70, 0)).toMatchObject({ kind: "off-view", turn: "left" });
    expect(towards(70, 0)).toMatchObject({ kind: "off-view", turn: "right" });
    // Turned round: still towards the nearer end, never drawn behind.
    expect(towards(-150, 0)).toMatchObject({ kind: "off-view", turn: "left" });
  });

  it("is in view when a long segment crosses the screen between its ends", () => {
    // Two points far left and far right of the screen, none on it: the line between is.
    const long = [[[-6000, 960], [8560, 960]]];
    expect(towards(0, 0, long)).toBeNull();
    // ... and off it once tilted away.
    expect(towards(0, 30, long)).toMatchObject({ kind: "off-view", turn: "down" });
  });
});
