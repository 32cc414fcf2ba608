/**
 * This phone's marks over its photo, at a constant size on the screen: the friend's mark or
 * line, the point of a line being drawn, and the landmarks, each a dot with its number on a
 * label placed clear of the others (markLayout.ts). A label is also the handle that grabs its
 * landmark (`data-landmark-label`, read by the gestures).
 */

import { t } from "../i18n";
import { clipLine, type Landmark, type TapSet } from "../landmarks";
import { labelPositions } from "../markLayout";
import { FRIEND_COLOUR, OUTLINE_COLOUR, landmarkColour } from "../palette";
import { pressTarget, type Gesture, type Grab } from "../gestures";
import { toPhoto, toScreen, type Point, type Size, type ViewTransform } from "../viewTransform";

/** The label attribute that marks a landmark's handle. */
const LABEL = "data-landmark-label";

/** CSS placing an absolutely positioned element's anchor at screen point `p`. */
export function at(p: Point): string {
  return `left:${p.x}px;top:${p.y}px`;
}

function ends(a: Point, b: Point): { x1: number; y1: number; x2: number; y2: number } {
  return { x1: a.x, y1: a.y, x2: b.x, y2: b.y };
}

/** The landmarks as drawn: a grabbed one where the finger is taking it. */
export function drawnLandmarks(taps: TapSet, gesture: Gesture, t: ViewTransform): Landmark[] {
  const dragged =
    gesture.kind === "press" && gesture.grab && gesture.moved
      ? { id: gesture.grab.id, at: toPhoto(t, pressTarget(gesture)) }
      : null;
  return taps.landmarks.map((l) => (dragged && l.id === dragged.id ? { ...l, ...dragged.at } : l));
}

/** The landmark whose label `target` is (or is in), where it is on the screen now. */
export function grabAt(target: EventTarget | null, taps: TapSet, t: ViewTransform): Grab | null {
  const label = target instanceof Element ? target.closest(`[${LABEL}]`) : null;
  const id = Number(label?.getAttribute("data-id"));
  const landmark = taps.landmarks.find((l) => l.id === id);
  return landmark ? { id, from: toScreen(t, landmark) } : null;
}

interface Props {
  taps: TapSet;
  /** The landmarks as drawn (drawnLandmarks). */
  landmarks: readonly Landmark[];
  selected: number | null;
  suspects: readonly number[];
  linePoint: Point | null;
  /** Photo points no label may cover besides the friend's mark (the answer's star). */
  keepClear: readonly Point[];
  photoSize: Size;
  view: Size;
  transform: ViewTransform;
}

export function Marks({ taps, landmarks, selected, suspects, linePoint, keepClear, photoSize, view, transform }: Props) {
  const screen = (p: Point): Point => toScreen(transform, p);
  const line = taps.friend_line ? clipLine(taps.friend_line, photoSize) : null;
  const labels = labelPositions(
    landmarks.map((l) => ({ id: l.id, at: screen(l) })),
    view,
    [...(taps.friend ? [taps.friend] : []), ...keepClear].map(screen),
  );
  return (
    <>
      <svg class="lines" width={view.width} height={view.height} aria-hidden="true">
        {line && (
          <g>
            <line {...ends(screen(line[0]), screen(line[1]))} stroke={OUTLINE_COLOUR} stroke-width="6" />
            <line {...ends(screen(line[0]), screen(line[1]))} stroke={FRIEND_COLOUR} stroke-width="3" />
          </g>
        )}
        {landmarks.map((l) => (
          <line
            key={l.id}
            {...ends(screen(l), labels.get(l.id) ?? screen(l))}
            stroke={landmarkColour(l.id)}
            stroke-width="2"
            stroke-dasharray="2 3"
          />
        ))}
      </svg>
      {linePoint && <div class="line-point" style={at(screen(linePoint))} />}
      {taps.friend && (
        <div class="friend-mark" data-testid="friend-mark" style={at(screen(taps.friend))}>
          <span>{t("tap.friend")}</span>
        </div>
      )}
      {landmarks.map((l) => {
        const p = screen(l);
        const label = labels.get(l.id) ?? p;
        const colour = landmarkColour(l.id);
        const suspect = suspects.includes(l.id);
        const state = `${l.id === selected ? " selected" : ""}${suspect ? " suspect" : ""}`;
        return (
          <div key={l.id}>
            <div class={`lm-point${state}`} style={`${at(p)};--c:${colour}`} />
            <div
              class={`lm-label${state}`}
              data-testid="landmark"
              data-id={String(l.id)}
              {...{ [LABEL]: "" }}
              style={`${at(label)};--c:${colour}`}
            >
              {l.id}
              {suspect ? "?" : ""}
              <span class="lm-hit" />
            </div>
          </div>
        );
      })}
    </>
  );
}
