/**
 * The photo view's pointers and wheel (pointers.ts) in Preact: listened to natively, once,
 * since a handler must be able to cancel the browser's default (no page scroll or zoom, no
 * text selection), and reading the view's props as they are now.
 */

import { useEffect, useRef, useState } from "preact/hooks";
import { IDLE, LOUPE_SHOW_MS, editOf, loupeTarget, type Gesture } from "../gestures";
import type { TapSet } from "../landmarks";
import type { PanZoom } from "../panZoom";
import { PointerGestures, listen } from "../pointers";
import type { Point } from "../viewTransform";
import type { Tap } from "../session";
import { grabAt } from "./Marks";

/** What the gestures do to the marks. */
export interface MarkHandlers {
  taps: TapSet;
  selected: number | null;
  /** A tap, with its precision at the zoom and aim it was made with. */
  onTap: (at: Tap) => void;
  onMove: (id: number, to: Tap) => void;
  onSelect: (id: number | null) => void;
}

/** The gesture in progress on the view whose element `box` holds, and the pointers' tracker. */
export function useGestures(
  box: { current: HTMLElement | null },
  panZoom: PanZoom,
  marks: MarkHandlers,
): { gesture: Gesture; gestures: PointerGestures } {
  const [gesture, setGesture] = useState<Gesture>(IDLE);
  const live = useRef(marks);
  live.current = marks;
  const made = useRef<PointerGestures | null>(null);
  made.current ??= new PointerGestures({
    now: () => panZoom.now(),
    origin: () => {
      const rect = box.current?.getBoundingClientRect();
      return { x: rect?.left ?? 0, y: rect?.top ?? 0 };
    },
    grabAt: (target, transform) => grabAt(target, live.current.taps, transform),
    transformed: (transform) => panZoom.set(transform),
    changed: setGesture,
    finished: (outcome, view) => {
      const now = live.current;
      const edit = editOf(outcome, view.transform, view.photo);
      if (edit?.kind === "place") now.onTap(edit.tap);
      else if (edit?.kind === "move") now.onMove(edit.id, edit.tap);
      else if (edit?.kind === "select") now.onSelect(now.selected === edit.id ? null : edit.id);
    },
    started: () => panZoom.gestureStarted(),
    ended: () => panZoom.gestureEnded(),
  });
  const gestures = made.current;

  useEffect(() => {
    const element = box.current;
    return element ? listen(element, window, gestures) : undefined;
  }, []);
  return { gesture, gestures };
}

/** The loupe's target while a press asks for it (gestures.ts), once it has lasted
 * LOUPE_SHOW_MS or moved. */
export function useLoupeTarget(gesture: Gesture): Point | null {
  const press = gesture.kind === "press" && !gesture.mouse ? gesture.since : null;
  const [due, setDue] = useState<number | null>(null);
  useEffect(() => {
    if (press === null) return undefined;
    const timer = setTimeout(() => setDue(press), LOUPE_SHOW_MS);
    return () => clearTimeout(timer);
  }, [press]);
  const target = loupeTarget(gesture);
  if (!target || gesture.kind !== "press") return null;
  return gesture.moved || due === gesture.since ? target : null;
}
