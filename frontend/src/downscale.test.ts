import { describe, expect, it } from "vitest";
import { downscaledSize, isUpright, preparePhoto, type PhotoDecoder } from "./downscale";
import { STORED_PHOTO_SIDE } from "./limits";
import type { Size } from "./viewTransform";

describe("the size sent", () => {
  it("brings the long side down to 2560 px and keeps the aspect", () => {
    const size = downscaledSize({ width: 8000, height: 6000 });
    expect(size).toEqual({ width: 2560, height: 1920 });
    const portrait = downscaledSize({ width: 3024, height: 4032 });
    expect(portrait.height).toBe(STORED_PHOTO_SIDE);
    expect(portrait.width).toBe(1920);
  });

  it("keeps the aspect within a pixel for awkward sizes", () => {
    for (const natural of [
      { width: 4033, height: 3025 },
      { width: 9999, height: 17 },
      { width: 2561, height: 2561 },
    ]) {
      const size = downscaledSize(natural);
      expect(Math.max(size.width, size.height)).toBeLessThanOrEqual(STORED_PHOTO_SIDE);
      expect(Math.min(size.width, size.height)).toBeGreaterThanOrEqual(1);
      const ratio = natural.width / natural.height;
      expect(Math.abs(size.width - size.height * ratio)).toBeLessThanOrEqual(ratio + 1);
    }
  });

  it("never enlarges a small photo", () => {
    expect(downscaledSize({ width: 640, height: 480 })).toEqual({ width: 640, height: 480 });
    expect(downscaledSize({ width: 2560, height: 100 })).toEqual({ width: 2560, height: 100 });
  });

  it("tells an upright picture from one the browser did not turn", () => {
    expect(isUpright({ width: 1920, height: 2560 }, { width: 3024, height: 4032 })).toBe(true);
    expect(isUpright({ width: 2560, height: 1920 }, { width: 3024, height: 4032 })).toBe(false);
    expect(isUpright({ width: 500, height: 500 }, { width: 1000, height: 1000 })).toBe(true);
  });
});

function fakeDecoder(upright: Size | null, decoded?: Size, jpeg = true): PhotoDecoder<string> & {
  decodedAt: Size[];
} {
  const decodedAt: Size[] = [];
  return {
    decodedAt,
    uprightSize: async () => upright,
    decodeAt: async (_file, size) => {
      decodedAt.push(size);
      return { picture: "bitmap", size: decoded ?? size };
    },
    encodeJpeg: async (_picture, size) =>
      jpeg ? new Blob([`jpeg ${size.width}x${size.height}`], { type: "image/jpeg" }) : null,
  };
}

describe("preparing the photo", () => {
  const file = Object.assign(new Blob(["raw"], { type: "image/jpeg" }), { name: "IMG_1.JPG" });

  it("decodes straight at the reduced size and sends a JPEG of that size", async () => {
    const decoder = fakeDecoder({ width: 8064, height: 6048 });
    const prepared = await preparePhoto(file, decoder);
    expect(decoder.decodedAt).toEqual([{ width: 2560, height: 1920 }]);
    expect(prepared.size).toEqual({ width: 2560, height: 1920 });
    expect(prepared.body.type).toBe("image/jpeg");
    expect(prepared.name).toBe("photo.jpg");
  });

  it("sends the original when the browser cannot decode it (HEIC on Chrome)", async () => {
    const heic = Object.assign(new Blob(["heic"], { type: "image/heic" }), { name: "IMG_2.HEIC" });
    const prepared = await preparePhoto(heic, fakeDecoder(null));
    expect(prepared.body).toBe(heic);
    expect(prepared.size).toBeNull();
    expect(prepared.name).toBe("IMG_2.HEIC");
  });

  it("sends the original when the decoded picture is not upright", async () => {
    const decoder = fakeDecoder({ width: 3024, height: 4032 }, { width: 2560, height: 1920 });
    expect((await preparePhoto(file, decoder)).body).toBe(file);
  });

  it("sends the original when encoding fails", async () => {
    const decoder = fakeDecoder({ width: 4000, height: 3000 }, undefined, false);
    expect((await preparePhoto(file, decoder)).body).toBe(file);
  });

  it("sends the original when decoding throws", async () => {
    const decoder: PhotoDecoder<string> = {
      uprightSize: async () => ({ width: 4000, height: 3000 }),
      decodeAt: async () => {
        throw new Error("out of memory");
      },
      encodeJpeg: async () => null,
    };
    expect((await preparePhoto(file, decoder)).body).toBe(file);
  });
});
