/**
 * The loupe: the photo magnified around the spot a pressing finger aims at (gestures.ts,
 * `loupeTarget`), drawn on a canvas beside the finger (markLayout.ts), with this phone's
 * marks as rings and a cross-hair on the exact spot.
 */

import { useLayoutEffect, useRef } from "preact/hooks";
import type { Landmark } from "../landmarks";
import { LOUPE_SIZE, loupePosition, loupeZoom } from "../markLayout";
import { FRIEND_COLOUR, OUTLINE_COLOUR, landmarkColour } from "../palette";
import { toPhoto, type Point, type Size, type ViewTransform } from "../viewTransform";

export interface LoupeProps {
  target: Point;
  view: Size;
  transform: ViewTransform;
  image: HTMLImageElement;
  photoSize: Size;
  landmarks: readonly Landmark[];
  marks: readonly Point[];
}

/** The magnified photo around the finger, with a cross-hair on the exact spot. */
export function Loupe({ target, view, transform, image, photoSize, landmarks, marks }: LoupeProps) {
  const canvas = useRef<HTMLCanvasElement>(null);
  const ratio = Math.min(3, window.devicePixelRatio || 1);
  const size = LOUPE_SIZE;
  const place = loupePosition(target, view);

  useLayoutEffect(() => {
    const context = canvas.current?.getContext("2d");
    if (!context) return;
    const zoom = loupeZoom(transform.scale);
    const centre = toPhoto(transform, target);
    context.setTransform(1, 0, 0, 1, 0, 0);
    context.fillStyle = "#000";
    context.fillRect(0, 0, size * ratio, size * ratio);
    const offset = (value: number): number => ratio * (size / 2 - value * zoom);
    context.setTransform(ratio * zoom, 0, 0, ratio * zoom, offset(centre.x), offset(centre.y));
    context.imageSmoothingEnabled = zoom < 3;
    if (image.complete && image.naturalWidth > 0) {
      context.drawImage(image, 0, 0, photoSize.width, photoSize.height);
    }
    context.setTransform(ratio, 0, 0, ratio, 0, 0);
    const inLoupe = (p: Point): Point => ({
      x: size / 2 + (p.x - centre.x) * zoom,
      y: size / 2 + (p.y - centre.y) * zoom,
    });
    const ring = (p: Point, colour: string, radius: number): void => {
      const q = inLoupe(p);
      context.beginPath();
      context.arc(q.x, q.y, radius, 0, 2 * Math.PI);
      context.lineWidth = 4;
      context.strokeStyle = OUTLINE_COLOUR;
      context.stroke();
      context.lineWidth = 2;
      context.strokeStyle = colour;
      context.stroke();
    };
    for (const l of landmarks) ring(l, landmarkColour(l.id), 8);
    for (const m of marks) ring(m, FRIEND_COLOUR, 12);
    // The cross-hair: open in the middle so the exact spot stays visible.
    const c = size / 2;
    const arms: Array<[number, number, number, number]> = [
      [c - 30, c, c - 5, c],
      [c + 5, c, c + 30, c],
      [c, c - 30, c, c - 5],
      [c, c + 5, c, c + 30],
    ];
    for (const [width, colour] of [
      [4, OUTLINE_COLOUR],
      [2, "#ffffff"],
    ] as const) {
      context.lineWidth = width;
      context.strokeStyle = colour;
      context.beginPath();
      for (const [x1, y1, x2, y2] of arms) {
        context.moveTo(x1, y1);
        context.lineTo(x2, y2);
      }
      context.stroke();
    }
  });

  return (
    <canvas
      ref={canvas}
      class="loupe"
      width={size * ratio}
      height={size * ratio}
      style={`left:${place.x}px;top:${place.y}px;width:${size}px;height:${size}px`}
      aria-hidden="true"
    />
  );
}
