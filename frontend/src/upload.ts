/**
 * The photo goes up behind the person's back: the phone shows its own downscaled copy at
 * once and takes taps on it, in the pixels the server will store, while the upload runs.
 *
 * Why the frame matches: the phone sends a JPEG of at most STORED_PHOTO_SIDE px on the long
 * side, upright and without EXIF (downscale.ts). The server re-encodes it (a fresh JPEG
 * without metadata) but never resizes a photo that small, nor turns one without EXIF
 * orientation (backend/photos/intake.py), so a tap at (x, y) here is (x, y) there. Should a
 * server be set to store smaller photos, the reply's size differs and `scaleTaps` maps the
 * taps made meanwhile onto the stored photo.
 */

import { ApiError, isRetryable, uploadPhoto } from "./api";
import type { PreparedPhoto } from "./downscale";
import type { FriendLine, TapSet } from "./landmarks";
import { backoffDelay, withRetry } from "./reconnect";
import type { Credentials, LensFields, PhotoFields, PhotoStored, SensorFields } from "./types";
import type { Size } from "./viewTransform";

/** What the phone shows as its photo: the stored one, or its own copy still on its way. */
export interface ShownPhoto {
  size: Size;
  /** Changes with each new photo (the view refits, the crops reload). */
  key: string;
  /** An object URL of the phone's own copy: the phone never downloads its own photo. */
  local?: string;
  /** True until the server has this photo: taps made on it wait (the tap saver holds). */
  pending?: boolean;
}

/** The phone's copy of a prepared photo, shown before it is sent; null when its size is not
 * known (the original file goes as it is, HEIC say: the server's size is awaited). */
export function localPhoto(prepared: PreparedPhoto, key: string): ShownPhoto | null {
  if (!prepared.size) return null;
  return { size: prepared.size, key, local: URL.createObjectURL(prepared.body), pending: true };
}

/** Retries of one upload before the phone says it failed (then Retry, or back online). */
const UPLOAD_RETRIES = 3;

/**
 * PUT the photo with its lens and the in-app camera's sensors (or null), retrying a lost
 * connection with backoff. Fields the server will not take (a lens of 65535 mm, say, or a
 * gravity of no length) must not cost the photo: refused (422), it goes again without
 * the sensors, then without the lens too, and the server assumes a phone's camera.
 */
export async function sendPhoto(
  credentials: Credentials,
  prepared: PreparedPhoto,
  lens: LensFields,
  sensors: SensorFields | null,
  onProgress: (fraction: number) => void,
): Promise<PhotoStored> {
  const send = (fields: PhotoFields): Promise<PhotoStored> =>
    withRetry(() => uploadPhoto(credentials, prepared.body, prepared.name, fields, onProgress), {
      retries: UPLOAD_RETRIES,
      isRetryable,
      delay: (n) => backoffDelay(n, { baseMs: 1500 }),
    });
  const attempts: PhotoFields[] = [...(sensors ? [{ ...lens, ...sensors }] : []), lens];
  if (Object.keys(lens).length > 0) attempts.push({});
  let refusal: unknown;
  for (const fields of attempts) {
    try {
      return await send(fields);
    } catch (error) {
      if (!(error instanceof ApiError && error.status === 422)) throw error;
      refusal = error;
    }
  }
  throw refusal;
}

/**
 * `taps` made on a photo of size `from`, on the same photo stored at size `to` (each axis
 * scaled on its own; a line's coefficients renormalised so that a^2 + b^2 = 1). Sigmas scale
 * with the mean of the two factors.
 */
export function scaleTaps(taps: TapSet, from: Size, to: Size): TapSet {
  const fx = to.width / from.width;
  const fy = to.height / from.height;
  if (fx === 1 && fy === 1) return taps;
  const sigma = (value: number | null): number | null => (value === null ? null : (value * (fx + fy)) / 2);
  const line = (l: FriendLine): FriendLine => {
    // a x + b y + c = 0 with x = x' / fx, y = y' / fy.
    const a = l.a / fx;
    const b = l.b / fy;
    const norm = Math.hypot(a, b);
    return { ...l, a: a / norm, b: b / norm, c: l.c / norm, sigma: sigma(l.sigma) };
  };
  return {
    landmarks: taps.landmarks.map((l) => ({ ...l, x: l.x * fx, y: l.y * fy, sigma: sigma(l.sigma) })),
    friend: taps.friend
      ? { ...taps.friend, x: taps.friend.x * fx, y: taps.friend.y * fy, sigma: sigma(taps.friend.sigma) }
      : null,
    friend_line: taps.friend_line ? line(taps.friend_line) : null,
  };
}
