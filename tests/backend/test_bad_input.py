"""Bad input, end to end: one table of what a phone (or anyone) may send wrong, each row
with the status and error code it gets, through the API, on SQLite and on PostgreSQL.

Each row runs on a fresh app and database with two phones paired. An accepted row's code
is the one the answer reports (``answer_error``), or none; a refused row's is the error's,
in the one shape. Rows of accepted photos also check what was stored.
"""

from __future__ import annotations

import io
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import httpx2
import numpy as np
import pytest
from fastapi.testclient import TestClient
from images import encoded, exif_of, png_claiming
from phones import (
    TEMPLE_PHOTOS,
    FakeClock,
    error_of,
    landmarks,
    photos_uploaded,
    scene,
    stored_photo,
)
from PIL import Image

from backend.settings import Settings
from testbed.client import Phone, start

WIDTH, HEIGHT = 400, 300  # of the made-up photos


@dataclass
class Search:
    """Two paired phones on a fresh app, and what the rows need around them."""

    client: TestClient
    starter: Phone
    joiner: Phone
    clock: FakeClock
    settings: Settings

    def with_photos(self) -> Search:
        """Both phones have uploaded their temple photo (640 x 480)."""
        photos_uploaded(self.starter, self.joiner, TEMPLE_PHOTOS)
        return self

    def stored_photo(self, role: str = "starter") -> Image.Image:
        answer = self.starter.ok("GET", f"/photo/{role}")
        assert answer.content.startswith(b"\xff\xd8\xff")  # JPEG, whatever came in
        image = Image.open(io.BytesIO(answer.content))
        image.load()
        return image


@dataclass(frozen=True)
class Row:
    name: str
    send: Callable[[Search], httpx2.Response]
    status: int
    code: str | None
    then: Callable[[Search, httpx2.Response], None] | None = None  # what was stored


# --- photos to send -------------------------------------------------------------------


def noise(mode: str = "RGB") -> Image.Image:
    pixels = np.random.default_rng(6).integers(0, 256, (HEIGHT, WIDTH, 3), dtype=np.uint8)
    return Image.fromarray(pixels).convert(mode)


def animated_gif() -> bytes:
    frames = [noise().convert("P"), noise().transpose(Image.Transpose.ROTATE_180).convert("P")]
    return encoded(frames[0], "GIF", save_all=True, append_images=frames[1:], duration=100)


def grey_ramp_16_bit() -> bytes:
    """A 16-bit grey PNG, black on the left to white on the right."""
    ramp = np.linspace(0, 65535, WIDTH).astype(np.uint16)
    return encoded(Image.fromarray(np.tile(ramp, (HEIGHT, 1))), "PNG")


def turned_by_exif() -> bytes:
    """A JPEG coded 400 x 300 whose EXIF says: turn 90 degrees to show it (300 x 400)."""
    return encoded(noise(), "JPEG", exif=exif_of(6), quality=90)


def upload(data: bytes, name: str = "photo.jpg") -> Callable[[Search], httpx2.Response]:
    return lambda search: search.starter.upload(data, name)


def stored_as(mode: str, size: tuple[int, int]) -> Callable[[Search, httpx2.Response], None]:
    def check(search: Search, _: httpx2.Response) -> None:
        stored = search.starter.state()["photos"]["starter"]
        assert (stored["width"], stored["height"]) == size
        photo = search.stored_photo()
        assert (photo.mode, photo.size) == (mode, size)

    return check


def ramp_kept(search: Search, answer: httpx2.Response) -> None:
    """16 bits scaled to 8, not clipped (which would turn it all white)."""
    grey = np.asarray(search.stored_photo().convert("L"), dtype=int)
    assert grey[:, :20].mean() < 30
    assert grey[:, -20:].mean() > 225


def tap_where_only_the_turned_photo_reaches(search: Search) -> httpx2.Response:
    """y = 350 is on the photo as shown (300 x 400), not as coded (400 x 300)."""
    stored = search.starter.upload(turned_by_exif())
    assert stored.json() == stored_photo(HEIGHT, WIDTH)
    return search.starter.tap(landmarks=[{"id": 1, "x": 250, "y": 350}], friend=[20, 390])


# --- taps to send ---------------------------------------------------------------------


def taps(role: str = "starter", /, **fields: Any) -> Callable[[Search], httpx2.Response]:
    """Both photos up, then these taps from ``role``'s phone."""
    return lambda search: getattr(search.with_photos(), role).tap(**fields)


def one_tap(x: Any, y: Any, **more: Any) -> Callable[[Search], httpx2.Response]:
    return taps(landmarks=[{"id": 1, "x": x, "y": y, **more}])


def tap_before_a_photo(search: Search) -> httpx2.Response:
    return search.starter.tap(landmarks=[{"id": 1, "x": 10, "y": 10}])


def raw_taps(body: bytes) -> Callable[[Search], httpx2.Response]:
    """Taps as bytes: JSON that Python's encoder would not write (NaN, Infinity)."""
    json = {"Content-Type": "application/json"}
    return lambda search: search.with_photos().starter.call("PUT", "/taps", json, content=body)


def nothing_stored(search: Search, _: httpx2.Response) -> None:
    assert search.starter.state()["photos"]["starter"] is None  # nothing half-stored


def names_landmark_3(_: Search, answer: httpx2.Response) -> None:
    assert "#3" in answer.json()["answer_error"]["message"]


def answer_to(starter_taps: dict[str, Any]) -> Callable[[Search], httpx2.Response]:
    """The starter taps ``starter_taps``; the joiner taps five true landmarks: the state the
    joiner gets back says what came of it."""

    def send(search: Search) -> httpx2.Response:
        search.with_photos()
        assert search.starter.tap(**starter_taps).status_code == 200
        return search.joiner.tap(landmarks=landmarks(SCENE.landmarks2))

    return send


SCENE = scene(5)
COLLINEAR = [(100 + 50 * n, 100 + 30 * n) for n in range(5)]


# --- who is asking --------------------------------------------------------------------


def get_state(
    token: str | None, session_id: str | None = None
) -> Callable[[Search], httpx2.Response]:
    def send(search: Search) -> httpx2.Response:
        headers = {"Authorization": f"Bearer {token}"} if token else {}
        return search.client.get(
            f"/api/sessions/{session_id or search.starter.session_id}", headers=headers
        )

    return send


def expired_token(search: Search) -> httpx2.Response:
    search.clock.advance(search.settings.session_ttl_seconds + 1)
    return search.client.get(search.starter.url(), headers=search.starter.auth)


def as_starter_at(path: str) -> Callable[[Search], httpx2.Response]:
    """The starter's valid token, at ``/api/sessions/<path>``: another session's id, or
    one that is none."""
    return lambda search: search.client.get(f"/api/sessions/{path}", headers=search.starter.auth)


def join(code: Callable[[Search], str]) -> Callable[[Search], httpx2.Response]:
    return lambda search: search.client.post("/api/sessions/join", json={"code": code(search)})


def deleted_sessions_code(search: Search) -> str:
    other, code = start(search.client)
    assert other.call("DELETE").status_code == 204
    return code


def events_after(last_event_id: str) -> Callable[[Search], httpx2.Response]:
    return lambda search: search.starter.call("GET", "/events", {"Last-Event-ID": last_event_id})


# --- the table ------------------------------------------------------------------------

NOT_A_PHOTO = b"These bytes are a sentence, not a photo, whatever the name says.\n" * 20
JPEG = encoded(noise(), "JPEG", quality=90)
TRUNCATED_JPEG = JPEG[: len(JPEG) // 2]
BOMB = png_claiming(20000, 20000)  # a few hundred bytes; decoded, 1.2 GB
SIXTY_MP = png_claiming(10000, 6000)
GIF_HEADER = b"GIF89a" + b"\0" * 100
HEIC = encoded(noise(), "HEIF", quality=90)
CMYK_JPEG = encoded(noise("CMYK"), "JPEG", quality=90)
STORED_RGB = stored_as("RGB", (WIDTH, HEIGHT))
STORED_TURNED = stored_as("RGB", (HEIGHT, WIDTH))
NAN = b'{"landmarks": [{"id": 1, "x": NaN, "y": 3}]}'
INFINITY = b'{"landmarks": [{"id": 1, "x": 3, "y": -Infinity}]}'
OVERFLOW = b'{"friend": {"x": 1e999, "y": 3}}'  # Python's JSON reads it as infinity
NOT_UTF_8 = b'{"landmarks": [{"id": 1, "x": 3, "y": "\xff"}]}'
MANY = [(n % 640, n % 480) for n in range(1000)]
MANY_IDS = [n % 999 + 1 for n in range(1000)]
SIXTY_FIVE = [{"id": i, "x": i % 600, "y": i % 400} for i in range(1, 66)]
DUPLICATES = landmarks(MANY[:3], [1, 2, 1])
TWICE_2 = [{"id": 2, "x": 1, "y": 1}, {"id": 2, "x": 5, "y": 5}]
COLLINEAR_TAPS = {"landmarks": landmarks(COLLINEAR), "friend": [500, 100]}
ON_3 = {"landmarks": landmarks(SCENE.landmarks1), "friend": list(SCENE.landmarks1[2])}
ZERO_LINE = {"a": 0, "b": 0, "c": 5}
MARK_AND_LINE = {"friend": [3, 3], "friend_line": {"a": 1, "b": 0, "c": -3}}
LINE_AS_A_LIST = {"friend_line": [1, 0, -5]}
MARKED_TWICE = {"friend": [10, 10], "friend_line": {"a": 1, "b": 0, "c": -5}}
LINE_OFF_THE_PHOTO = {"a": 1, "b": 0, "c": 1000}  # x = -1000


def too_large(search: Search) -> httpx2.Response:
    return search.starter.upload(b"\xff\xd8\xff" + bytes(search.settings.max_body_bytes))


def another_token(search: Search) -> httpx2.Response:
    return get_state(start(search.client)[0].token)(search)


def another_session_id(search: Search) -> httpx2.Response:
    return as_starter_at(start(search.client)[0].session_id)(search)


TABLE = [
    # Photos: what they are is read from their bytes, never from a name or a content type.
    Row("not an image, named .jpg", upload(NOT_A_PHOTO), 415, "unsupported_media_type"),
    Row("a GIF header, named .jpg", upload(GIF_HEADER), 415, "unsupported_media_type"),
    Row("a truncated JPEG", upload(TRUNCATED_JPEG), 422, "invalid_photo"),
    Row("an empty file", upload(b"", "empty.jpg"), 422, "empty_photo", nothing_stored),
    Row("a PNG decompression bomb, 20000 x 20000", upload(BOMB), 413, "photo_too_large"),
    Row("a small PNG claiming 10000 x 6000", upload(SIXTY_MP, "small.png"), 413, "photo_too_large"),
    Row("a body over the size limit", too_large, 413, "body_too_large"),
    Row("a HEIC photo, converted", upload(HEIC, "IMG_0001.HEIC"), 200, None, STORED_RGB),
    Row("an animated GIF: not accepted", upload(animated_gif()), 415, "unsupported_media_type"),
    Row("a CMYK JPEG, stored RGB", upload(CMYK_JPEG), 200, None, STORED_RGB),
    Row("a 16-bit PNG", upload(grey_ramp_16_bit(), "scan.png"), 200, None, ramp_kept),
    Row("an EXIF-rotated photo", tap_where_only_the_turned_photo_reaches, 200, None, STORED_TURNED),
    # Taps: numbers on the photo, each landmark once, not too many.
    Row("taps before a photo", tap_before_a_photo, 409, "photo_missing"),
    Row("NaN in taps", raw_taps(NAN), 422, "invalid_request"),
    Row("Infinity in taps", raw_taps(INFINITY), 422, "invalid_request"),
    Row("1e999 in taps", raw_taps(OVERFLOW), 422, "invalid_request"),
    Row("a word in taps", one_tap("left", 3), 422, "invalid_request"),
    Row("a word for x", one_tap("left", 1), 422, "invalid_request"),
    Row("a landmark id of 0", taps(landmarks=[{"id": 0, "x": 1, "y": 1}]), 422, "invalid_request"),
    Row("a friend mark with a w", taps(friend={"x": 1, "y": 2, "w": 3}), 422, "invalid_request"),
    Row("a field no taps have", taps(epipole1=[1, 2]), 422, "invalid_request"),
    Row("a friend line as [a, b, c]", taps("joiner", **LINE_AS_A_LIST), 422, "invalid_request"),
    Row("a number in a string", one_tap("12", 3), 422, "invalid_request"),
    Row("true as a coordinate", taps(friend={"x": True, "y": 3}), 422, "invalid_request"),
    Row("a friend mark as [x, y]", raw_taps(b'{"friend": [3, 3]}'), 422, "invalid_request"),
    Row("a precision of 0", taps(friend={"x": 3, "y": 3, "sigma": 0}), 422, "invalid_request"),
    Row("a negative precision", one_tap(3, 3, sigma=-2.0), 422, "invalid_request"),
    Row("1e308 in taps", one_tap(1e308, 3), 422, "outside_photo"),
    Row("a tap outside the photo", one_tap(641, 3), 422, "outside_photo"),
    Row("a tap far right of the photo", one_tap(700, 10), 422, "outside_photo"),
    Row("a tap above the photo", one_tap(10, -1), 422, "outside_photo"),
    Row("a friend mark outside the photo", taps(friend=[-0.5, 3]), 422, "outside_photo"),
    Row("a friend mark right of the photo", taps(friend=[641, 10]), 422, "outside_photo"),
    Row("the joiner's mark above the photo", taps("joiner", friend=[10, -3]), 422, "outside_photo"),
    Row("a friend line with a = b = 0", taps(friend_line=ZERO_LINE), 422, "invalid_line"),
    Row("a friend line 0 = 1", taps(friend_line={"a": 0, "b": 0, "c": 1}), 422, "invalid_line"),
    Row("a friend line off the photo", taps(friend_line=LINE_OFF_THE_PHOTO), 422, "invalid_line"),
    Row("a friend mark and a line", taps(**MARK_AND_LINE), 422, "conflicting_inputs"),
    Row("the joiner's mark and a line", taps("joiner", **MARKED_TWICE), 422, "conflicting_inputs"),
    Row("duplicate landmark ids", taps(landmarks=DUPLICATES), 422, "duplicate_landmark"),
    Row("landmark #2 twice", taps(landmarks=TWICE_2), 422, "duplicate_landmark"),
    Row("1000 landmarks", taps(landmarks=landmarks(MANY, MANY_IDS)), 422, "too_many_landmarks"),
    Row("65 landmarks", taps(landmarks=SIXTY_FIVE), 422, "too_many_landmarks"),
    Row("taps that are not UTF-8", raw_taps(NOT_UTF_8), 400, "bad_request"),
    # Taps that are fine but cannot be answered: accepted, and the answer says why.
    Row("collinear landmarks", answer_to(COLLINEAR_TAPS), 200, "collinear_landmarks"),
    Row("the friend mark on #3", answer_to(ON_3), 200, "epipole_on_landmark", names_landmark_3),
    # Tokens: a token opens its own session, while it lasts.
    Row("a missing token", get_state(None), 401, "unauthorized"),
    Row("a wrong token", get_state("b" * 43), 401, "unauthorized"),
    Row("a token that is no token", get_state("not-a-token"), 401, "unauthorized"),
    Row("an expired token", expired_token, 401, "unauthorized"),
    Row("another session's token", another_token, 403, "forbidden"),
    # Join codes: single use, while valid (a used one, an expired one: test_sessions.py).
    Row("a code replayed after the end", join(deleted_sessions_code), 404, "invalid_join_code"),
    # Session ids, unknown or malformed, with the valid token of another session.
    Row("an unknown session id", as_starter_at("0" * 32), 403, "forbidden"),
    Row("the id of another live session", another_session_id, 403, "forbidden"),
    Row("a session id ../x", as_starter_at("../x"), 404, "not_found"),
    Row("a session id ..%2Fx", as_starter_at("..%2Fx"), 404, "not_found"),
    Row("a session id of 10000 characters", as_starter_at("7" * 10_000), 403, "forbidden"),
    Row("a unicode session id", as_starter_at("s\u00e9ance-\U0001f600"), 403, "forbidden"),
    Row("a session id with a NUL byte", as_starter_at("abc%00def"), 403, "forbidden"),
    Row("a malformed session id, no token", get_state(None, "%ff%fe"), 401, "unauthorized"),
    # The event stream: a Last-Event-ID no event can have.
    Row("a Last-Event-ID past 64 bits", events_after(str(2**64)), 422, "invalid_request"),
    Row("a Last-Event-ID that is no number", events_after("last"), 422, "invalid_request"),
]


def code_of(answer: httpx2.Response) -> str | None:
    """The refusal's code (in the one shape), or what the answer says about itself."""
    if answer.status_code >= 400:
        return error_of(answer)
    error = answer.json().get("answer_error")
    return None if error is None else str(error["code"])


@pytest.mark.parametrize("row", TABLE, ids=[row.name for row in TABLE])
def test_bad_input(
    row: Row,
    client: TestClient,
    starter: Phone,
    joiner: Phone,
    clock: FakeClock,
    settings: Settings,
) -> None:
    search = Search(client, starter, joiner, clock, settings)
    answer = row.send(search)
    assert answer.status_code == row.status, answer.text[:500]
    assert code_of(answer) == row.code, answer.text[:500]
    if row.then is not None:
        row.then(search, answer)


def test_the_table_has_one_row_per_name() -> None:
    assert len({row.name for row in TABLE}) == len(TABLE)
