/**
 * A frame of the live view matched to the photo on the server (`POST .../reanchor`, the
 * server's OpenCV features and a homography): what Align sends, and the quiet check of the
 * video's focal length (focalCheck.ts). Frames are small (JPEG, long side FRAME_SIDE) and
 * few: one per tap of Align, one per opening for the check; the server keeps none.
 */

import { ApiError, reanchor } from "../api";
import { t } from "../i18n";
import type { Credentials } from "../types";
import type { Matrix3, Vector3 } from "./orientation";
import type { Size } from "./pointer";

/** A frame sent to be matched: JPEG, this long side, this quality. */
const FRAME_SIDE = 960;
const FRAME_QUALITY = 0.8;

/** What the server found: the turn from the photo's camera frame into the frame's, and the
 * frame's focal length over its long side (the video's, at any size of it). */
export interface Matched {
  rotation: Matrix3;
  focalPerLongSide: number;
}

/** The live view's frame of the moment, small (long side FRAME_SIDE). */
export function drawFrame(element: HTMLVideoElement, video: Size): HTMLCanvasElement {
  const k = Math.min(1, FRAME_SIDE / Math.max(video.width, video.height));
  const canvas = document.createElement("canvas");
  canvas.width = Math.round(video.width * k);
  canvas.height = Math.round(video.height * k);
  canvas.getContext("2d")?.drawImage(element, 0, 0, canvas.width, canvas.height);
  return canvas;
}

/**
 * `canvas` (a frame of the live video) matched to the session's photo; the server measures
 * the frame's focal length from the match (api.ts's reanchor).
 * Throws ApiError: the server's refusal (`frame_not_matched`), no connection, an answer that
 * is not a turn.
 */
export async function matchFrame(credentials: Credentials, canvas: HTMLCanvasElement): Promise<Matched> {
  const blob = await new Promise<Blob | null>((resolve) => canvas.toBlob(resolve, "image/jpeg", FRAME_QUALITY));
  if (!blob) throw new Error(t("live.unreadable"));
  const found = await reanchor(credentials, blob);
  const rotation = asMatrix(found.rotation);
  if (!rotation) throw new ApiError(200, "bad_answer", t("live.notMatched"));
  return { rotation, focalPerLongSide: found.frame_focal_px / Math.max(canvas.width, canvas.height) };
}

/** Three rows of three finite numbers as a matrix, else null. */
export function asMatrix(rows: readonly (readonly number[])[] | null): Matrix3 | null {
  if (!rows || rows.length !== 3 || !rows.every((row) => row.length === 3 && row.every(Number.isFinite))) return null;
  const [a, b, c] = rows as [number[], number[], number[]];
  return [a as unknown as Vector3, b as unknown as Vector3, c as unknown as Vector3];
}
