"""One drawing of the answer, two renderers: the phone's SVG layer (in Chromium) and the
server's OpenCV overlay (the drawing alone, ``?layer=true``) put the curve, the frame and the
border arrow in the same place of the photo, because both render the shapes the server
computed once (shared_solver/drawing). Each may choose its stroke widths and font sizes, so
the test compares where the friend-coloured strokes are, in photo px, within a stroke.
"""

from __future__ import annotations

import base64
import io
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from PIL import Image

from testbed.browser import play
from testbed.browser.phone import Phone, expect
from testbed.browser.screen import screen_pixels, set_answer_shown
from testbed.scenes import NO_PHONES_LANDMARKS2

PHOTO = (640, 480)
# The friend's colour (palette.json), and how far a pixel may be from it to count as drawn in
# it: the inside of a stroke, not its anti-aliased edge.
FRIEND = np.array([0xFF, 0xD4, 0x00])
NEAR_COLOUR = 60
# A friend mark in the starter's photo that the temple's landmarks put off the joiner's
# photo (below it, to the right), px.
OFF_PHOTO_MARK = (620.0, 20.0)

OVERLAY_LAYER = """async () => {
    const { session_id, token } = JSON.parse(localStorage.getItem("buddy-search.session"));
    const headers = { Authorization: `Bearer ${token}` };
    const url = `/api/sessions/${session_id}/overlay/joiner?layer=true`;
    const bytes = new Uint8Array(await (await fetch(url, { headers })).arrayBuffer());
    let text = "";
    for (const byte of bytes) text += String.fromCharCode(byte);
    return btoa(text);
}"""


def friend_coloured(rgb: np.ndarray) -> np.ndarray:
    return np.abs(rgb.astype(int) - FRIEND).max(axis=-1) < NEAR_COLOUR


def opencv_strokes(page: Phone) -> np.ndarray:
    """(H, W) mask of the photo's pixels the overlay paints in the friend's colour."""
    data = base64.b64decode(page.evaluate(OVERLAY_LAYER))
    with Image.open(io.BytesIO(data)) as layer:
        rgba = np.array(layer.convert("RGBA"))
    assert rgba.shape[:2] == (PHOTO[1], PHOTO[0])
    mask: np.ndarray = (rgba[..., 3] > 128) & friend_coloured(rgba[..., :3])
    return mask


def svg_strokes(page: Phone, folder: Path) -> tuple[np.ndarray, float]:
    """(M, 2) photo px of the screen pixels the phone's answer layer paints in the friend's
    colour (the screen with the layer shown against the screen without it), and the view's
    scale (CSS px per photo px)."""
    origin = np.array(page.photo_to_screen(0.0, 0.0))
    scale = page.photo_to_screen(1.0, 0.0)[0] - origin[0]
    shots = []
    for shown in (False, True):
        set_answer_shown(page, shown)
        shots.append(screen_pixels(page, folder, f"answer-{shown}"))
    (plain, _), (drawn, ratio) = shots
    painted = (np.abs(drawn - plain).max(axis=-1) > 30) & friend_coloured(drawn)
    rows, cols = np.nonzero(painted)
    client = (np.column_stack([cols, rows]) + 0.5) / ratio
    photo = (client - origin) / scale
    inside = np.all((photo >= 0) & (photo < PHOTO), axis=1)
    return photo[inside], scale


def clear_from(page: Phone) -> float:
    """The photo's first row (px) below the status, which lies translucent over its top and
    dims what is drawn under it (its padding included: the words' own box ends above it)."""
    bottom = float(
        page.get_by_test_id("result-text").evaluate(
            "(text) => text.closest('.status').getBoundingClientRect().bottom"
        )
    )
    top = page.photo_to_screen(0.0, 0.0)[1]
    scale = page.photo_to_screen(0.0, 1.0)[1] - top
    return (bottom - top) / scale


def distance_to(mask: np.ndarray) -> np.ndarray:
    """(H, W) distance in px from each photo pixel to the nearest set pixel of ``mask``."""
    return np.asarray(cv2.distanceTransform((~mask).astype(np.uint8), cv2.DIST_L2, 5))


def pixels(mask: np.ndarray) -> np.ndarray:
    rows, cols = np.nonzero(mask)
    return np.column_stack([cols, rows]).astype(float) + 0.5


def at(field: np.ndarray, points: np.ndarray) -> np.ndarray:
    x = np.clip(points[:, 0].astype(int), 0, field.shape[1] - 1)
    y = np.clip(points[:, 1].astype(int), 0, field.shape[0] - 1)
    return np.asarray(field[y, x])


def near_polylines(polylines: list[list[list[float]]], within: float) -> np.ndarray:
    """(H, W) mask of the photo's pixels within ``within`` px of the shapes' polylines."""
    mask = np.zeros((PHOTO[1], PHOTO[0]), np.uint8)
    lines = [np.round(np.array(line) * 16).astype(np.int32) for line in polylines]
    cv2.polylines(mask, lines, False, 1, 1, cv2.LINE_8, 4)
    return distance_to(mask > 0) <= within


def drawing_of(page: Phone) -> dict[str, Any]:
    drawing: dict[str, Any] = play.answer_in(page, "joiner")["drawing"]
    return drawing


def same_curve(page: Phone, folder: Path) -> None:
    """Every dot of the phone's dotted curve is on the overlay's curve, and the overlay's
    curve has a dot of the phone's near every point of it."""
    drawn, scale = svg_strokes(page, folder)
    overlay = opencv_strokes(page)
    stroke = 1.5 / scale + 2.0  # half the phone's dot plus the overlay's line, photo px
    assert len(drawn) > 100
    assert at(distance_to(overlay), drawn).max() <= stroke
    # The overlay's curve, its label aside (pixels on the shapes' polylines), where the
    # phone's is not under the status.
    curve = pixels(overlay & near_polylines(drawing_of(page)["curve"]["polylines"], 2.0))
    curve = curve[curve[:, 1] > clear_from(page) + 2]
    spacing = 7 / scale  # the phone's dots are this far apart on screen
    phone = np.zeros_like(overlay)
    phone[drawn[:, 1].astype(int), drawn[:, 0].astype(int)] = True
    assert len(curve) > 300
    assert at(distance_to(phone), curve).max() <= spacing / 2 + stroke


def same_frame(page: Phone, folder: Path) -> None:
    """The frame's strokes (its brackets, and the region's outline when drawn) are in the same
    place in both; the label and its leader, outside the frame's box, are each renderer's."""
    box = np.array(page.get_by_test_id("answer-frame").numbers("x0", "y0", "x1", "y1"))
    drawn, scale = svg_strokes(page, folder)
    stroke = 1.5 / scale + 2.0
    pad = 3 / scale + 2.0
    clear = clear_from(page) + 2

    def kept(points: np.ndarray) -> np.ndarray:
        inside = np.all((points >= box[:2] - pad) & (points <= box[2:] + pad), axis=1)
        found: np.ndarray = points[inside & (points[:, 1] > clear)]
        return found

    shapes = drawing_of(page)["frame"]
    strokes = opencv_strokes(page)
    phone = kept(drawn)
    # The overlay's label is kept on the photo even when the frame's edge is off it: only its
    # pixels on the brackets and the outline count.
    overlay = kept(pixels(strokes & near_polylines(shapes["brackets"] + shapes["outline"], 2.0)))
    assert len(phone) > 50
    assert len(overlay) > 50
    assert at(distance_to(strokes), phone).max() <= stroke
    mask = np.zeros_like(strokes)
    mask[phone[:, 1].astype(int), phone[:, 0].astype(int)] = True
    assert at(distance_to(mask), overlay).max() <= stroke


def same_arrow(page: Phone, folder: Path) -> None:
    """Both arrows lie on the ray from the photo's centre towards the friend, their tips at
    the same spot by the border; their lengths and heads are each renderer's."""
    arrow = drawing_of(page)["arrow"]
    tip, direction = np.array(arrow["tip"]), np.array(arrow["direction"])
    drawn, scale = svg_strokes(page, folder)
    centre = np.array(PHOTO) / 2

    def on_ray(points: np.ndarray) -> np.ndarray:
        offset = points - centre
        across = np.abs(offset[:, 0] * direction[1] - offset[:, 1] * direction[0])
        found: np.ndarray = points[across < 3 / scale + 2]
        return found

    for painted in (on_ray(pixels(opencv_strokes(page))), on_ray(drawn)):
        along = (painted - centre) @ direction
        end = painted[np.argmax(along)]
        assert np.hypot(*(end - tip)) <= 3 / scale + 3.0, (end, tip)
        # A shaft along the ray behind the tip, not a blob that happens to touch it.
        behind = (tip - centre) @ direction - along
        assert np.count_nonzero((behind > 10) & (behind < 30)) > 20


def test_the_phone_and_the_overlay_draw_the_answer_in_the_same_place(
    server: str, pixel: Phone, iphone: Phone, tmp_path: Path
) -> None:
    """The curve at four landmarks, then the frame at five: where the phone's
    SVG puts them in the photo is where the overlay's picture puts them."""
    joiner = play.to_the_curve(server, pixel, iphone)
    same_curve(joiner, tmp_path)

    play.find_landmarks(joiner, NO_PHONES_LANDMARKS2[4:], first_id=5)
    expect(joiner.get_by_test_id("result-position")).to_be_visible()
    expect(joiner.get_by_test_id("answer-frame")).to_be_visible()
    same_frame(joiner, tmp_path)


def test_the_phone_and_the_overlay_point_the_same_way_to_a_friend_off_the_photo(
    server: str, pixel: Phone, iphone: Phone, tmp_path: Path
) -> None:
    """The temple's landmarks with the friend marked top right in the starter's photo put
    them below the joiner's photo, to the right: both arrows point there from the same tip."""
    truth = play.scene(5, seed=16)
    starter, joiner = play.start_and_join(server, pixel, iphone, photos=True)
    play.marked_and_found(starter, joiner, OFF_PHOTO_MARK, truth.landmarks1, truth.landmarks2)
    expect(joiner.get_by_test_id("answer-border-arrow")).to_be_visible()
    same_arrow(joiner, tmp_path)
