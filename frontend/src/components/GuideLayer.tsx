/**
 * Where the landmark to find must be (docs/app.md, "Guided tapping"): its band, the line in
 * this photo the other phone's tap allows, widened by the answer's uncertainty (95 %), and,
 * when the server's search of the other photo's patch along it is sure, a ring on the
 * suggested spot. Drawn under the answer's frame, in the landmark's colour, with strokes of
 * a constant size on the screen; it takes no taps (a tap inside it places the landmark).
 */

import { useEffect, useState } from "preact/hooks";
import { fetchSuggestion } from "../api";
import { outlinePoints } from "../guidance";
import { OUTLINE_COLOUR, landmarkColour } from "../palette";
import type { Credentials, LandmarkBand } from "../types";
import { toScreen, type Point, type Size, type ViewTransform } from "../viewTransform";

/** The suggestion's ring and label, screen px. */
const RING = 15;
const LABEL_GAP = 6;

export interface Guide {
  id: number;
  band: LandmarkBand;
  /** The suggested spot, photo px, or null: find it by eye. */
  spot: Point | null;
}

interface Props {
  guide: Guide;
  transform: ViewTransform;
  view: Size;
}

export function GuideLayer({ guide, transform: t, view }: Props) {
  const colour = landmarkColour(guide.id);
  const screen = (p: Point): Point => toScreen(t, p);
  const start = screen({ x: guide.band.start[0], y: guide.band.start[1] });
  const end = screen({ x: guide.band.end[0], y: guide.band.end[1] });
  const spot = guide.spot ? screen(guide.spot) : null;
  return (
    <svg class="guide-layer" width={view.width} height={view.height} aria-hidden="true">
      <polygon
        data-testid="landmark-band"
        data-id={String(guide.id)}
        points={outlinePoints(guide.band, screen)}
        fill={colour}
        fill-opacity="0.16"
        stroke={colour}
        stroke-width="1.5"
        stroke-dasharray="6 4"
      />
      <line x1={start.x} y1={start.y} x2={end.x} y2={end.y} stroke={colour} stroke-width="1" stroke-opacity="0.7" />
      {spot && (
        <g data-testid="suggested-spot" data-id={String(guide.id)} data-x={String(guide.spot?.x)} data-y={String(guide.spot?.y)}>
          <circle cx={spot.x} cy={spot.y} r={RING} fill="none" stroke={OUTLINE_COLOUR} stroke-width="5" />
          <circle cx={spot.x} cy={spot.y} r={RING} fill="none" stroke={colour} stroke-width="2.5" />
          <text class="guide-label" x={spot.x + RING + LABEL_GAP} y={spot.y + 5} fill={colour} stroke={OUTLINE_COLOUR}>
            #{guide.id}?
          </text>
        </g>
      )}
    </svg>
  );
}

/**
 * The suggested spot for landmark `id` in your photo under answer `version`, asked once per
 * answer and landmark: undefined while asked, null when there is none or it could not be
 * had (a suggestion is a help, never a reason to show an error).
 */
export function useSuggestion(
  credentials: Credentials,
  id: number | null,
  version: number | null,
): Point | null | undefined {
  const [found, setFound] = useState<{ key: string; spot: Point | null } | null>(null);
  const key = id === null || version === null ? null : `${id}@${version}`;
  useEffect(() => {
    if (key === null || id === null) return;
    let current = true;
    fetchSuggestion(credentials, credentials.role, id)
      .then((reply) => current && setFound({ key, spot: reply.spot ?? null }))
      .catch(() => current && setFound({ key, spot: null }));
    return () => {
      current = false;
    };
  }, [key]);
  if (key === null) return null;
  return found && found.key === key ? found.spot : undefined;
}
