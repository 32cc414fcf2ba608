/**
 * Where the photo is drawn in its view: screen <-> photo pixels under zoom and pan.
 *
 * Screen points are relative to the view's top-left corner (client coordinates minus the
 * view's bounding rect). A photo pixel (x, y) is drawn at (tx + scale * x, ty + scale * y).
 * Taps are always kept in photo pixels, so they do not depend on zoom or screen size.
 */

export interface Point {
  readonly x: number;
  readonly y: number;
}

export interface Size {
  readonly width: number;
  readonly height: number;
}

export interface ViewTransform {
  readonly scale: number;
  readonly tx: number;
  readonly ty: number;
}

/**
 * Screen px along each side of the view covered by words or controls (the status over the
 * photo's top, the buttons along its bottom) or kept as a margin. The photo's edge may come
 * in that far from the view's edge, so that any part of it, the answer at its very top
 * included, can be shown clear of them.
 */
export interface Insets {
  readonly top: number;
  readonly right: number;
  readonly bottom: number;
  readonly left: number;
}

export const NO_INSETS: Insets = { top: 0, right: 0, bottom: 0, left: 0 };

/** How far in the photo can be zoomed, relative to the fitted view. */
export const MAX_ZOOM = 8;
/** Zoomed in at least this far (screen px per photo px), even for small photos. */
export const MIN_MAX_SCALE = 2;

function clamp(value: number, low: number, high: number): number {
  return Math.min(Math.max(value, low), high);
}

/** The whole photo in the view, as large as fits, centred ("contain"). */
export function fitTransform(view: Size, photo: Size): ViewTransform {
  const scale = Math.min(view.width / photo.width, view.height / photo.height);
  return {
    scale,
    tx: (view.width - photo.width * scale) / 2,
    ty: (view.height - photo.height * scale) / 2,
  };
}

/** A fitted photo smaller than this share of its view opens larger (openingTransform): a
 * 3:4 photo on an iPhone 13 upright fills 91 % of its view fitted, and opens filling it,
 * 9 % of its height a drag away; on a Pixel 7 it fills 98 % and opens whole. */
export const OPENING_SHARE = 0.95;

/**
 * The photo as it opens: fitted when that fills (nearly) all of the view; a photo of another
 * shape than the view (a landscape photo on an upright phone, drawn fitted on a third of the
 * screen) fills the view instead ("cover"), centred on `around` (photo px; its middle when
 * not given): large enough to tap, the rest a drag or the whole-photo button away.
 */
export function openingTransform(view: Size, photo: Size, around: Point | null = null): ViewTransform {
  const fitted = fitTransform(view, photo);
  const share = (photo.width * photo.height * fitted.scale ** 2) / (view.width * view.height);
  if (share >= OPENING_SHARE) return fitted;
  const cover = Math.max(view.width / photo.width, view.height / photo.height);
  const scale = Math.min(cover, scaleLimits(view, photo).max);
  return centreOn(around ?? { x: photo.width / 2, y: photo.height / 2 }, scale, view, photo);
}

/** Smallest scale (the fitted photo) and largest (zoomed in MAX_ZOOM times, at least 2). */
export function scaleLimits(view: Size, photo: Size): { min: number; max: number } {
  const min = fitTransform(view, photo).scale;
  return { min, max: Math.max(min * MAX_ZOOM, MIN_MAX_SCALE) };
}

export function toScreen(t: ViewTransform, p: Point): Point {
  return { x: t.tx + t.scale * p.x, y: t.ty + t.scale * p.y };
}

export function toPhoto(t: ViewTransform, p: Point): Point {
  return { x: (p.x - t.tx) / t.scale, y: (p.y - t.ty) / t.scale };
}

export function isInsidePhoto(p: Point, photo: Size): boolean {
  return p.x >= 0 && p.y >= 0 && p.x <= photo.width && p.y <= photo.height;
}

/**
 * The nearest allowed transform: scale within the limits; along each axis the photo either
 * covers the view (no empty margin beyond its edge) or, when smaller, is centred; with
 * `slack`, its edge may also come in as far as the covered band along that side (never
 * further), so that what the band would hide can be brought out from under it.
 */
export function clampTransform(t: ViewTransform, view: Size, photo: Size, slack: Insets = NO_INSETS): ViewTransform {
  const { min, max } = scaleLimits(view, photo);
  const scale = clamp(t.scale, min, max);
  // Centred, or anywhere between the photo's far edge at the far band and its near edge at
  // the near band (with no slack: covering the view, or centred when smaller).
  const axis = (offset: number, viewSide: number, photoSide: number, before: number, after: number): number => {
    const drawn = photoSide * scale;
    const centred = (viewSide - drawn) / 2;
    return clamp(offset, Math.min(centred, viewSide - after - drawn), Math.max(centred, before));
  };
  return {
    scale,
    tx: axis(t.tx, view.width, photo.width, slack.left, slack.right),
    ty: axis(t.ty, view.height, photo.height, slack.top, slack.bottom),
  };
}

/** Zoom by `factor` about the screen point `centre`, which stays put unless clamping moves it. */
export function zoomAbout(
  t: ViewTransform,
  factor: number,
  centre: Point,
  view: Size,
  photo: Size,
  slack: Insets = NO_INSETS,
): ViewTransform {
  const { min, max } = scaleLimits(view, photo);
  const scale = clamp(t.scale * factor, min, max);
  const anchor = toPhoto(t, centre);
  return clampTransform(
    { scale, tx: centre.x - anchor.x * scale, ty: centre.y - anchor.y * scale },
    view,
    photo,
    slack,
  );
}

export function panBy(
  t: ViewTransform,
  dx: number,
  dy: number,
  view: Size,
  photo: Size,
  slack: Insets = NO_INSETS,
): ViewTransform {
  return clampTransform({ scale: t.scale, tx: t.tx + dx, ty: t.ty + dy }, view, photo, slack);
}

function midpoint(a: Point, b: Point): Point {
  return { x: (a.x + b.x) / 2, y: (a.y + b.y) / 2 };
}

function distance(a: Point, b: Point): number {
  return Math.hypot(a.x - b.x, a.y - b.y);
}

/**
 * Two fingers moved from `from` to `to` (screen points), starting at transform `start`:
 * the scale follows the fingers' spread, and the photo point that was under their midpoint
 * stays under it (zoom about the pinch centre, and pan with it).
 */
export function pinchTransform(
  start: ViewTransform,
  from: readonly [Point, Point],
  to: readonly [Point, Point],
  view: Size,
  photo: Size,
  slack: Insets = NO_INSETS,
): ViewTransform {
  const before = distance(from[0], from[1]);
  const factor = before > 0 ? distance(to[0], to[1]) / before : 1;
  const { min, max } = scaleLimits(view, photo);
  const scale = clamp(start.scale * factor, min, max);
  const anchor = toPhoto(start, midpoint(from[0], from[1]));
  const centre = midpoint(to[0], to[1]);
  return clampTransform(
    { scale, tx: centre.x - anchor.x * scale, ty: centre.y - anchor.y * scale },
    view,
    photo,
    slack,
  );
}

/** Zoomed to `scale` with the photo point `p` in the middle of the view (as far as allowed). */
export function centreOn(p: Point, scale: number, view: Size, photo: Size, slack: Insets = NO_INSETS): ViewTransform {
  return clampTransform(
    { scale, tx: view.width / 2 - p.x * scale, ty: view.height / 2 - p.y * scale },
    view,
    photo,
    slack,
  );
}

/** Whether the view shows the whole photo as fitted: not zoomed in, nor moved aside (to
 * bring the answer out from under the status). */
export function isFitted(t: ViewTransform, view: Size, photo: Size): boolean {
  const fitted = fitTransform(view, photo);
  return t.scale <= fitted.scale * 1.001 && Math.abs(t.tx - fitted.tx) < 0.5 && Math.abs(t.ty - fitted.ty) < 0.5;
}
