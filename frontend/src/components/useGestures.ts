/**
 * The photo view's pointers and wheel (pointers.ts) in Preact: listened to natively, once,
 * since a handler must be able to cancel the browser's default (no page scroll or zoom, no
 * text selection), and reading the view's props as they are now.
 */

import { useEffect, useRef, useState } from "preact/hooks";
import { IDLE, LOUPE_SHOW_MS, editOf, type Gesture } from "../gestures";
import type { TapSet } from "../landmarks";
import type { PanZoom } from "../panZoom";
import { PointerGestures, listen } from "../pointers";
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
  const loupeDue = useRef<ReturnType<typeof setTimeout> | undefined>(undefined);
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
    changed: (next) => {
      clearTimeout(loupeDue.current);
      if (next.kind === "press" && !next.moved) {
        // A finger down that has not moved draws as no gesture at all until its loupe is due
        // (LOUPE_SHOW_MS; a mouse never has one): no render on a finger's down, part of a
        // tap's time to the screen on a slow phone (docs/slow-phone.md).
        setGesture(IDLE);
        if (next.mouse) return;
        // Each change of the press sets it anew, timed from the press's own start.
        loupeDue.current = setTimeout(
          () => setGesture(next),
          Math.max(0, next.since + LOUPE_SHOW_MS - performance.now()), // since: the event's time stamp
        );
        return;
      }
      setGesture(next);
    },
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
    const stop = element ? listen(element, window, gestures) : undefined;
    return () => {
      clearTimeout(loupeDue.current);
      stop?.();
    };
  }, []);
  return { gesture, gestures };
}
