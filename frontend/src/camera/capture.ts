/**
 * The picture at the shutter: the camera's own photo (ImageCapture.takePhoto, Chromium),
 * else the video's current frame drawn on a canvas (Safari, Firefox), as a JPEG.
 *
 * Why the shape check: the photo must be the frame the person saw, upright as on screen,
 * since down is read in that frame (gravity.ts). Phones deliver the video turned to the
 * screen; a takePhoto that comes back turned the other way (portrait preview, landscape
 * photo) is not trusted and the frame is used instead.
 */

import { browserDecoder, isUpright, JPEG_QUALITY } from "../downscale";

interface ImageCaptureLike {
  takePhoto(): Promise<Blob>;
}
type ImageCaptureClass = new (track: MediaStreamTrack) => ImageCaptureLike;

export async function takePicture(video: HTMLVideoElement, track: MediaStreamTrack): Promise<File> {
  const shown = { width: video.videoWidth, height: video.videoHeight };
  const ImageCapture = (window as { ImageCapture?: ImageCaptureClass }).ImageCapture;
  if (ImageCapture) {
    try {
      const photo = await new ImageCapture(track).takePhoto();
      const size = await browserDecoder().uprightSize(photo);
      // A PNG from some cameras (Chromium's fake one): shrunk to a JPEG like any photo.
      const kind = photo.type.split("/")[1] || "jpeg";
      if (size && isUpright(size, shown)) return new File([photo], `camera.${kind}`, { type: photo.type });
    } catch {
      // Some cameras refuse takePhoto while streaming: the frame will do.
    }
  }
  return frame(video, shown);
}

function frame(video: HTMLVideoElement, size: { width: number; height: number }): Promise<File> {
  const canvas = document.createElement("canvas");
  canvas.width = size.width;
  canvas.height = size.height;
  canvas.getContext("2d")?.drawImage(video, 0, 0, size.width, size.height);
  return new Promise((resolve, reject) =>
    canvas.toBlob(
      (blob) => (blob ? resolve(new File([blob], "camera.jpeg", { type: "image/jpeg" })) : reject(new Error("no frame"))),
      "image/jpeg",
      JPEG_QUALITY,
    ),
  );
}
