import { describe, expect, it } from "vitest";
import templePng from "../../tests/data/temple/templeSR0003.png?inline";
import lensJpeg from "./fixtures/lens.jpg?inline";
import { lensFields, lensNote, readLens } from "./lens";

// A 32 x 24 JPEG made with Pillow, with the EXIF of a Pixel 7's photo: Make, Model,
// FocalLength 6.81, FocalLengthIn35mmFilm 24, DigitalZoomRatio 1, and what must never
// leave the phone: GPS position, BodySerialNumber, DateTimeOriginal.
const PHOTO = bytes(lensJpeg);

/** The bytes of a file Vite inlined as a data: URL. */
function bytes(dataUrl: string): Uint8Array<ArrayBuffer> {
  const text = atob(dataUrl.slice(dataUrl.indexOf(",") + 1));
  return Uint8Array.from(text, (c) => c.charCodeAt(0));
}

describe("the lens of a photo", () => {
  it("is read from the file's EXIF: the lens tags and nothing else", async () => {
    const fields = await readLens(new Blob([PHOTO], { type: "image/jpeg" }));
    expect(fields).toEqual({
      focal_35mm: 24,
      focal_mm: 6.81,
      make: "Google",
      model: "Pixel 7",
      digital_zoom: 1,
    });
    expect(JSON.stringify(fields)).not.toMatch(/SERIAL|2026|48|latitude/i);
  });

  it("is nothing for a photo without EXIF, or not a photo", async () => {
    expect(await readLens(new Blob([bytes(templePng)], { type: "image/png" }))).toEqual({});
    expect(await readLens(new Blob(["not a photo"]))).toEqual({});
  });

  it("leaves out what no lens can be", () => {
    expect(lensFields({ FocalLengthIn35mmFormat: 0, FocalLength: Number.NaN, Make: "  ", Model: "X\0" })).toEqual({
      model: "X",
    });
    expect(lensFields({ DigitalZoomRatio: 0 })).toEqual({ digital_zoom: 0 });
    expect(lensFields(undefined)).toEqual({});
  });

  it("is said to the person: told by the phone, by the photo, or assumed", () => {
    const size = { width: 2560, height: 1920, scale: 1 };
    expect(lensNote({ ...size, lens: { focal_35mm: 24, told_by: "phone" } })).toBe(
      "Your phone told us its lens (24 mm): the answer uses it.",
    );
    expect(lensNote({ ...size, lens: { focal_35mm: 26.4, told_by: "photo" } })).toContain("Your photo told us its lens (26 mm)");
    expect(lensNote({ ...size, lens: null })).toContain("a typical phone camera is assumed");
    expect(lensNote(null)).toBeNull();
  });
});
