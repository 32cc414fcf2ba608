import { describe, expect, it } from "vitest";
import { TAP_PRECISION } from "./limits";
import { lineSigma, tapSigma } from "./precision";
import { fitTransform, zoomAbout } from "./viewTransform";

const { finger_css: finger, loupe_css: loupe, min_sigma_px: least } = TAP_PRECISION;

describe("how precise a tap is", () => {
  it("is a finger's spread in photo px at the zoom of the tap", () => {
    // A 2560 x 1920 photo fitted to a 412 px wide view: 1 CSS px is 6.2 photo px.
    const fitted = fitTransform({ width: 412, height: 560 }, { width: 2560, height: 1920 });
    expect(tapSigma(fitted.scale, "finger")).toBeCloseTo(finger / fitted.scale, 2);
    expect(tapSigma(fitted.scale, "loupe")).toBeCloseTo(loupe / fitted.scale, 2);
  });

  it("gets finer as the photo is zoomed in, and with the loupe", () => {
    const view = { width: 412, height: 560 };
    const photo = { width: 2560, height: 1920 };
    const fitted = fitTransform(view, photo);
    const zoomed = zoomAbout(fitted, 4, { x: 200, y: 280 }, view, photo);
    expect(tapSigma(zoomed.scale, "finger")).toBeLessThan(tapSigma(fitted.scale, "finger"));
    expect(tapSigma(fitted.scale, "loupe")).toBeLessThan(tapSigma(fitted.scale, "finger"));
  });

  it("is never claimed finer than the least sigma", () => {
    expect(tapSigma(50, "loupe")).toBe(least);
    expect(tapSigma(50, "finger")).toBe(least);
  });

  it("of a line through two taps is the less precise tap's", () => {
    expect(lineSigma(2.5, 4)).toBe(4);
    expect(lineSigma(4, 2.5)).toBe(4);
  });

  it("takes its constants from the limits the server reads", () => {
    const custom = { finger_css: 3, loupe_css: 1, min_sigma_px: 0.5 };
    expect(tapSigma(1, "finger", custom)).toBe(3);
    expect(tapSigma(1, "loupe", custom)).toBe(1);
    expect(tapSigma(4, "loupe", custom)).toBe(0.5);
  });
});
