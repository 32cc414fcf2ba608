/**
 * The photo is made small on the phone before it is sent: at most STORED_PHOTO_SIDE (2560)
 * px on the long side (what the server stores anyway), upright, as a JPEG. Sending 3 MB instead of 12 MB matters
 * on a venue's weak network.
 *
 * Never a full-size canvas: iOS Safari draws nothing on a canvas beyond about 16.7 MP, and a
 * 48 MP photo is far beyond. A photo up to 16.7 MP is decoded whole (off the page's thread)
 * and drawn small on a canvas of the reduced size; a larger one is decoded straight at the
 * reduced size (createImageBitmap with resizeWidth/resizeHeight).
 * When the browser cannot decode it at all (HEIC on Chrome, old Safari) the original file is
 * sent as it is: the server converts HEIC or says clearly why it cannot.
 */

import { STORED_PHOTO_SIDE } from "./limits";
import type { Size } from "./viewTransform";

export const JPEG_QUALITY = 0.9;

/** The size to send: the long side at most `maxSide`, the aspect kept, never enlarged. */
export function downscaledSize(natural: Size, maxSide: number = STORED_PHOTO_SIDE): Size {
  const long = Math.max(natural.width, natural.height);
  if (long <= maxSide) return { width: natural.width, height: natural.height };
  const factor = maxSide / long;
  const side = (value: number): number => Math.min(maxSide, Math.max(1, Math.round(value * factor)));
  return { width: side(natural.width), height: side(natural.height) };
}

/** Whether a decoded picture of size `got` is the upright photo of size `upright` (not turned). */
export function isUpright(got: Size, upright: Size): boolean {
  const landscape = (s: Size): boolean => s.width > s.height;
  const square = (s: Size): boolean => Math.abs(s.width - s.height) <= 1;
  return square(upright) || square(got) || landscape(got) === landscape(upright);
}

/** What the browser offers to read and redraw a photo (fakes in the tests). */
export interface PhotoDecoder<Picture> {
  /** The upright size (EXIF orientation applied), or null when the photo cannot be decoded. */
  uprightSize(file: Blob): Promise<Size | null>;
  /** The photo decoded at `size`, upright; null when that is not possible. */
  decodeAt(file: Blob, size: Size): Promise<{ picture: Picture; size: Size } | null>;
  /** The picture drawn on a canvas of `size`, as a JPEG; null when that fails. */
  encodeJpeg(picture: Picture, size: Size, quality: number): Promise<Blob | null>;
}

export interface PreparedPhoto {
  body: Blob;
  /** What was sent, in px; null when the original file goes as it is. */
  size: Size | null;
  /** The file name to send. */
  name: string;
}

/** The photo to upload: downscaled JPEG when the browser can decode it, else the original. */
export async function preparePhoto<Picture>(
  file: Blob & { name?: string },
  decoder: PhotoDecoder<Picture>,
  maxSide: number = STORED_PHOTO_SIDE,
): Promise<PreparedPhoto> {
  const original: PreparedPhoto = { body: file, size: null, name: file.name || "photo" };
  try {
    const upright = await decoder.uprightSize(file);
    if (!upright || upright.width < 1 || upright.height < 1) return original;
    const target = downscaledSize(upright, maxSide);
    const decoded = await decoder.decodeAt(file, target);
    if (!decoded || !isUpright(decoded.size, upright)) return original;
    const jpeg = await decoder.encodeJpeg(decoded.picture, target, JPEG_QUALITY);
    if (!jpeg || jpeg.size === 0) return original;
    return { body: jpeg, size: target, name: "photo.jpg" };
  } catch {
    return original;
  }
}

// --- the browser's decoder -------------------------------------------------------------------

type Drawable = ImageBitmap | HTMLImageElement;

/** Photos up to this many pixels are decoded whole before they are made small (decodeAt);
 * larger ones (a 48 MP mode) at the small size, which never holds the whole picture. */
export const FULL_DECODE_PX = 16_777_216;

function loadImage(file: Blob): Promise<HTMLImageElement | null> {
  return new Promise((resolve) => {
    const url = URL.createObjectURL(file);
    const image = new Image();
    image.decoding = "async";
    image.onload = () => resolve(image);
    image.onerror = () => {
      URL.revokeObjectURL(url);
      resolve(null);
    };
    image.src = url;
  });
}

/**
 * Reads sizes with an <img> (its naturalWidth/Height apply the EXIF orientation), decodes
 * at the target size with createImageBitmap (falling back to drawing the <img> scaled,
 * which also never makes a full-size canvas), encodes on a canvas of the target size.
 */
export function browserDecoder(): PhotoDecoder<Drawable> {
  let image: HTMLImageElement | null = null;
  return {
    async uprightSize(file) {
      image = await loadImage(file);
      if (!image || image.naturalWidth === 0) return null;
      return { width: image.naturalWidth, height: image.naturalHeight };
    },
    async decodeAt(file, size) {
      if (typeof createImageBitmap === "function") {
        try {
          // Up to FULL_DECODE_PX the photo is decoded whole and made small by the canvas:
          // Chromium decodes a whole picture on a worker thread but resizes on the page's
          // own (a 12 MP photo: 1.2 s of the page's time at 4x CPU against 0.1 s).
          const whole = image !== null && image.naturalWidth * image.naturalHeight <= FULL_DECODE_PX;
          const options: ImageBitmapOptions = whole
            ? { imageOrientation: "from-image" }
            : { resizeWidth: size.width, resizeHeight: size.height, resizeQuality: "high", imageOrientation: "from-image" };
          const bitmap = await createImageBitmap(file, options);
          const got = { width: bitmap.width, height: bitmap.height };
          if (image && !isUpright(got, { width: image.naturalWidth, height: image.naturalHeight })) {
            bitmap.close(); // orientation ignored by this browser: draw the <img> instead
          } else {
            return { picture: bitmap, size: got };
          }
        } catch {
          // resize options unsupported: the <img> below
        }
      }
      if (!image) return null;
      return { picture: image, size: { width: image.naturalWidth, height: image.naturalHeight } };
    },
    async encodeJpeg(picture, size, quality) {
      const canvas = document.createElement("canvas");
      canvas.width = size.width;
      canvas.height = size.height;
      const context = canvas.getContext("2d");
      if (!context) return null;
      context.imageSmoothingEnabled = true;
      // Down to half size, bilinear ("low") samples every photo pixel's neighbourhood well
      // enough; finer filters cost a slowed phone's page 1 s more on a 12 MP photo (the draw
      // is done on the page's thread when the JPEG is made: 1.4 s against 0.46 s at 4x CPU).
      const width = "naturalWidth" in picture ? picture.naturalWidth : picture.width;
      context.imageSmoothingQuality = size.width >= width / 2 ? "low" : "high";
      context.drawImage(picture, 0, 0, size.width, size.height);
      if ("close" in picture) picture.close();
      if (image) URL.revokeObjectURL(image.src);
      const blob = await new Promise<Blob | null>((resolve) =>
        canvas.toBlob(resolve, "image/jpeg", quality),
      );
      canvas.width = canvas.height = 0; // frees the canvas memory at once on iOS
      return blob;
    },
  };
}
