/**
 * The lens of the photo, read from the chosen file's EXIF before the phone shrinks it (the
 * shrunk JPEG keeps no metadata) and sent with the upload: the solver then knows the photo's
 * focal length instead of assuming a typical phone's (backend/photos/lens.py).
 *
 * Only the tags that describe the lens are read, never GPS, serial numbers or dates. Many
 * phones (iOS Safari in particular) strip them from photos picked in the browser: then
 * nothing is sent, and the server assumes a phone's main camera.
 */

import { t } from "./i18n";
import type { LensFields, PhotoStored } from "./types";

/**
 * The EXIF tags read, and nothing else (exifr's names: FocalLengthIn35mmFormat is EXIF's
 * FocalLengthIn35mmFilm), by the block they are in; GPS and the other blocks are skipped.
 */
const READ = {
  ifd0: { pick: ["Make", "Model"] },
  exif: { pick: ["FocalLength", "FocalLengthIn35mmFormat", "DigitalZoomRatio"] },
  gps: false,
  interop: false,
  ifd1: false,
  xmp: false,
};

function positive(value: unknown): number | undefined {
  return typeof value === "number" && Number.isFinite(value) && value > 0 ? value : undefined;
}

function words(value: unknown): string | undefined {
  const text = typeof value === "string" ? value.replace(/\0/g, "").trim() : "";
  return text ? text : undefined;
}

/** The form fields of the upload from EXIF tags as exifr names them (absent ones left out). */
export function lensFields(tags: unknown): LensFields {
  if (typeof tags !== "object" || tags === null) return {};
  const read = tags as Record<string, unknown>;
  const zoom = read.DigitalZoomRatio;
  const fields: LensFields = {
    focal_35mm: positive(read.FocalLengthIn35mmFormat),
    focal_mm: positive(read.FocalLength),
    make: words(read.Make),
    model: words(read.Model),
    // 0 is EXIF's "no digital zoom".
    digital_zoom: typeof zoom === "number" && Number.isFinite(zoom) && zoom >= 0 ? zoom : undefined,
  };
  return Object.fromEntries(Object.entries(fields).filter(([, value]) => value !== undefined));
}

/**
 * The lens fields of `file`'s EXIF; none when it has none or cannot be read. The file is
 * read whole (a HEIC photo may keep its EXIF anywhere): never a name or URL, which exifr
 * would fetch.
 */
export async function readLens(file: Blob): Promise<LensFields> {
  try {
    const exifr = await Promise.race([lensReader(), giveUp(READER_WAIT_MS)]);
    return lensFields(await exifr.parse(await file.arrayBuffer(), READ));
  } catch {
    return {};
  }
}

type Exifr = (typeof import("exifr/dist/lite.esm.mjs"))["default"];

/** How long a chosen photo waits for exifr's chunk, ms: a phone with no signal that never
 * fetched it shows its photo without the lens rather than not at all. */
const READER_WAIT_MS = 1500;
let reader: Promise<Exifr> | null = null;

/**
 * exifr, a chunk of its own: only a chosen photo needs it, never the start screen. The
 * photo step fetches it ahead (while there is a signal, before the photo is chosen); a
 * failed fetch is tried again next time.
 */
export function lensReader(): Promise<Exifr> {
  reader ??= import("exifr/dist/lite.esm.mjs").then(
    (module) => module.default,
    (error: unknown) => {
      reader = null;
      throw error;
    },
  );
  return reader;
}

function giveUp(ms: number): Promise<never> {
  return new Promise((_, reject) => setTimeout(() => reject(new Error("no lens reader")), ms));
}

/** What the phone says of its photo's lens, once the photo is stored. */
export function lensNote(photo: PhotoStored | null | undefined): string | null {
  if (!photo) return null;
  const lens = photo.lens;
  if (!lens) return t("photo.lensUnknown");
  const mm = Math.round(lens.focal_35mm);
  return lens.told_by === "phone" ? t("photo.lensByPhone", { mm }) : t("photo.lensByPhoto", { mm });
}
