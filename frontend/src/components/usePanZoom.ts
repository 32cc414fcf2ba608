/**
 * The photo view's transform in Preact (panZoom.ts): measured before the first paint and on
 * every resize, opened again for a new photo (around `around`), redrawn on every change.
 */

import { useEffect, useLayoutEffect, useRef, useState } from "preact/hooks";
import { prefersReducedMotion } from "../a11y/motion";
import { PanZoom, type Frames, type PanZoomState } from "../panZoom";
import type { Insets, Point, Size } from "../viewTransform";

const BROWSER_FRAMES: Frames = {
  request: (step) => requestAnimationFrame(step),
  cancel: (id) => cancelAnimationFrame(id),
  now: () => performance.now(),
};

/** The controller and its state now, for the view whose element `box` holds. */
export function usePanZoom(
  box: { current: HTMLElement | null },
  photoUrl: string,
  photoSize: Size,
  insets: Insets,
  busy: () => boolean,
  around: Point | null,
): { panZoom: PanZoom; state: PanZoomState } {
  const [state, setState] = useState<PanZoomState>({ view: null, transform: null, gliding: false });
  const made = useRef<PanZoom | null>(null);
  made.current ??= new PanZoom(photoSize, setState, BROWSER_FRAMES);
  const panZoom = made.current;
  panZoom.reducedMotion = prefersReducedMotion();
  useEffect(() => panZoom.setInsets(insets, busy()), [insets.top, insets.right, insets.bottom, insets.left]);

  useLayoutEffect(() => {
    const element = box.current;
    if (!element) return;
    const measure = (): void => {
      const rect = element.getBoundingClientRect();
      panZoom.resize({ width: rect.width, height: rect.height });
    };
    measure();
    const observer = new ResizeObserver(measure);
    observer.observe(element);
    return () => observer.disconnect();
  }, []);

  // What the photo opens around is read when a photo opens, not followed after: the view
  // moves by itself only to bring the answer into view (panZoom.ts).
  const opensAround = useRef(around);
  opensAround.current = around;
  useEffect(() => panZoom.showPhoto(photoSize, opensAround.current), [photoUrl, photoSize.width, photoSize.height]);
  useEffect(() => () => panZoom.stopGlide(), []);
  return { panZoom, state };
}
