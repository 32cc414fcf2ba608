/**
 * The tap surface: the stored photo, zoomable and pannable, with this phone's marks drawn
 * on top at a constant size, and the loupe while a finger presses. It publishes its view
 * transform as data attributes (data-scale, data-tx, data-ty): photo pixel (x, y) is at
 * (rect.left + tx + scale * x, rect.top + ty + scale * y); `data-gliding` while the view glides
 * to the answer (reframe.ts), `data-settling` while an answer waits for the fingers' quiet
 * to be brought into view (panZoom.ts).
 *
 * The controls over the photo (the whole-photo button, the arrow to the answer) are not
 * inside the photo view but beside it, in a layer of their own over it. Browsers move a
 * finger's touch onto a nearby element that takes taps (Chromium's touch adjustment), and
 * they pass over an element that takes taps when an element inside it takes them too: were
 * the photo view the controls' parent, every touch near a control would go to the control.
 * As siblings they compete (the view takes taps by listening for click: pointers.ts), and a
 * touch on the photo beside a control stays on the photo.
 *
 * The parts, one job each: the transform over time (panZoom.ts, usePanZoom.ts), pointers and
 * the wheel (pointers.ts, useGestures.ts, the state machine in gestures.ts), the marks
 * (Marks.tsx), the answer (AnswerLayer.tsx) and its arrow (AnswerArrow.tsx), the loupe
 * (Loupe.tsx), the guide (GuideLayer.tsx).
 */

import { t as tr } from "../i18n";
import { useEffect, useRef, useState } from "preact/hooks";
import { PHOTO_DESCRIPTION_ID } from "../a11y/PhotoDescription";
import { loupeTarget, type Gesture } from "../gestures";
import type { TapSet } from "../landmarks";
import type { AnswerView } from "../answer";
import type { Box } from "../reframe";
import type { Tap } from "../session";
import { isFitted, type Insets, type Point, type Size, type ViewTransform } from "../viewTransform";
import { AnswerArrow } from "./AnswerArrow";
import { AnswerLayer, answerBox } from "./AnswerLayer";
import { GuideLayer, type Guide } from "./GuideLayer";
import { FitIcon } from "./icons";
import { Loupe } from "./Loupe";
import { Marks, drawnLandmarks } from "./Marks";
import { useGestures } from "./useGestures";
import { usePanZoom } from "./usePanZoom";

export interface Focus {
  id: number;
  nonce: number;
}

interface Props {
  photoUrl: string;
  photoSize: Size;
  /** The answer, drawn over the photo by the phone (AnswerLayer). */
  answer: AnswerView;
  /** Where the landmark to find must be, under the answer (GuideLayer). */
  guide: Guide | null;
  /** Screen px along each side of the view covered by the status: an answer is brought
   * into the rest. */
  insets: Insets;
  taps: TapSet;
  selected: number | null;
  suspects: readonly number[];
  linePoint: Point | null;
  /** Photo points no label may cover (the answer's star). */
  keepClear: readonly Point[];
  focus: Focus | null;
  /** A tap, with its precision at the zoom and aim it was made with. */
  onTap: (at: Tap) => void;
  onMove: (id: number, to: Tap) => void;
  onSelect: (id: number | null) => void;
}

export function PhotoView(props: Props) {
  const { photoSize, taps } = props;
  const box = useRef<HTMLDivElement>(null);
  const image = useRef<HTMLImageElement>(null);
  // The photo whose picture has loaded, or failed to: per URL, so that a new photo's is
  // never taken for the old one's (a cached picture may load before an effect could reset
  // a flag, and then "Loading" stayed over the new photo).
  const [loadedUrl, setLoadedUrl] = useState<string | null>(null);
  const loaded = loadedUrl === props.photoUrl;
  // Whether a finger is down, for the view's moves that wait for the gesture's end.
  const busy = useRef<() => boolean>(() => false);
  // The server's photo did not come (no signal after an offline reload): said so, not
  // "Loading"; it is asked for again when the phone is back online (session/sync.ts).
  const [failedUrl, setFailedUrl] = useState<string | null>(null);
  const failed = failedUrl === props.photoUrl;
  const { panZoom, state } = usePanZoom(box, props.photoUrl, photoSize, props.insets, () => busy.current(), opensAround(taps, props.guide));
  const { gesture, gestures } = useGestures(box, panZoom, props);
  busy.current = () => gestures.active;
  const { view, transform, gliding } = state;

  // "Re-check #3": zoom to that landmark.
  useEffect(() => {
    const landmark = taps.landmarks.find((l) => l.id === props.focus?.id);
    if (landmark) panZoom.focus(landmark);
  }, [props.focus?.nonce]);

  // A new answer, or one that moved noticeably: brought into view, after the gesture in
  // progress if there is one.
  const focus = answerBox(props.answer);
  const shownBox: Box | null = focus && props.answer.news ? focus : null;
  const boxKey = shownBox ? `${shownBox.centre.x},${shownBox.centre.y},${shownBox.half.x}` : "";
  useEffect(() => {
    if (shownBox) panZoom.answer(shownBox, gestures.active);
  }, [boxKey, view !== null && transform !== null]);

  const ready = view !== null && transform !== null;
  const attributes = ready
    ? {
        "data-photo-width": String(photoSize.width),
        "data-photo-height": String(photoSize.height),
        "data-scale": String(transform.scale),
        "data-tx": String(transform.tx),
        "data-ty": String(transform.ty),
        ...(gliding ? { "data-gliding": "" } : {}),
        ...(state.settling ? { "data-settling": "" } : {}),
      }
    : {};

  const zoomed = ready && !isFitted(transform, view, photoSize);
  return (
    <>
      <div
        ref={box}
        class="photo-view"
        data-testid="photo-view"
        role="application"
        aria-label={tr("photo.viewLabel")}
        aria-describedby={PHOTO_DESCRIPTION_ID}
        tabIndex={-1}
        {...attributes}
      >
        {ready && (
          <Drawing
            {...props}
            view={view}
            transform={transform}
            gesture={gesture}
            image={image}
            loaded={loaded}
            onLoaded={() => setLoadedUrl(props.photoUrl)}
            failed={failed}
            onFailed={() => setFailedUrl(props.photoUrl)}
          />
        )}
      </div>
      {ready && (
        <div class="photo-controls">
          {zoomed && <p class="pan-hint">{tr("photo.panHint")}</p>}
          <AnswerArrow
            answer={props.answer}
            photoSize={photoSize}
            transform={transform}
            view={view}
            insets={props.insets}
            onShow={() => shownBox && panZoom.bringIntoView(shownBox)}
          />
          {zoomed && (
            <button
              type="button"
              class="fit-button"
              data-testid="fit"
              aria-label={tr("photo.wholePhoto")}
              onClick={() => panZoom.fit()}
            >
              <FitIcon />
            </button>
          )}
        </div>
      )}
    </>
  );
}

interface DrawingProps extends Props {
  view: Size;
  transform: ViewTransform;
  gesture: Gesture;
  image: { current: HTMLImageElement | null };
  loaded: boolean;
  onLoaded: () => void;
  failed: boolean;
  onFailed: () => void;
}

/**
 * The part of the photo that matters as it opens (a landscape photo on an upright phone is
 * filled to the view's height, and only part of it shows): the friend this phone marked,
 * else the next landmark's suggested spot, else the middle of its band; null: the middle.
 */
export function opensAround(taps: TapSet, guide: Guide | null): Point | null {
  if (taps.friend) return { x: taps.friend.x, y: taps.friend.y };
  if (guide?.spot) return guide.spot;
  if (!guide) return null;
  const { start, end } = guide.band;
  return { x: (start[0] + end[0]) / 2, y: (start[1] + end[1]) / 2 };
}

/** The picture: photo, guide, marks, the answer on top, loupe. */
function Drawing(props: DrawingProps) {
  const { view, transform: t, gesture, taps, photoSize } = props;
  const layer = `width:${photoSize.width}px;height:${photoSize.height}px;transform:translate(${t.tx}px,${t.ty}px) scale(${t.scale})`;
  const landmarks = drawnLandmarks(taps, gesture, t);
  const target = loupeTarget(gesture); // a press reaches here moved, or held LOUPE_SHOW_MS

  return (
    <>
      <img
        ref={props.image}
        class="layer"
        src={props.photoUrl}
        // A photo that did not come draws no broken-image sign over the marks.
        style={props.failed ? `${layer};visibility:hidden` : layer}
        alt={tr("photo.yourPhoto")}
        draggable={false}
        onLoad={props.onLoaded}
        onError={props.onFailed}
      />
      {props.guide && <GuideLayer guide={props.guide} transform={t} view={view} />}
      <Marks
        taps={taps}
        landmarks={landmarks}
        selected={props.selected}
        suspects={props.suspects}
        linePoint={props.linePoint}
        keepClear={props.keepClear}
        photoSize={photoSize}
        view={view}
        transform={t}
      />
      <AnswerLayer answer={props.answer} transform={t} view={view} clearTop={props.insets.top} />
      {target && props.image.current && (
        <Loupe
          target={target}
          view={view}
          transform={t}
          image={props.image.current}
          photoSize={photoSize}
          landmarks={landmarks}
          marks={taps.friend ? [taps.friend] : []}
        />
      )}
      {!props.loaded && (
        <p class="photo-loading" data-testid="photo-loading">
          {props.failed ? tr("photo.backOnline") : tr("photo.loading")}
        </p>
      )}
    </>
  );
}
