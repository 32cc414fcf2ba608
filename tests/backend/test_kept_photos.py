"""A replica keeps the photos it read lately by name, a minute after their last use at most,
within its bytes."""

from __future__ import annotations

import numpy as np
from fastapi.testclient import TestClient
from phones import Phones, landmarks, scene

from backend.photos.intake import StoredPhoto
from backend.photos.kept import KeptPhotos
from backend.photos.pictures import decode_photo, encode_image
from backend.photos.repository import Photos
from backend.wiring import Services
from testbed.client import Phone


class Reads:
    """A photo store that counts its reads."""

    def __init__(self, size: int = 1000) -> None:
        self.count = 0
        self.size = size

    def __call__(self) -> StoredPhoto:
        self.count += 1
        return StoredPhoto(data=bytes(self.size), width=4, height=3, scale=1.0)


def test_a_photo_is_read_once_by_name_and_again_a_minute_after_its_last_use() -> None:
    now = [0.0]
    kept = KeptPhotos(max_bytes=10_000, max_seconds=60, clock=lambda: now[0])
    reads = Reads()
    first = kept.get(("s", "starter", 3), reads)
    assert kept.get(("s", "starter", 3), reads) is first
    kept.get(("s", "starter", 5), reads)  # replaced: another name
    kept.get(("s", "joiner", 3), reads)
    assert reads.count == 3
    now[0] = 59.0
    assert kept.get(("s", "starter", 3), reads) is first  # used: kept until 119 s
    now[0] = 61.0
    assert kept.get(("s", "starter", 3), reads) is first
    assert kept.get(("s", "starter", 5), reads) is not None  # unused since 0 s: read again
    assert reads.count == 4
    now[0] = 121.5
    assert kept.get(("s", "starter", 3), reads) is not first
    assert reads.count == 5


def test_the_least_recently_used_goes_first_when_the_bytes_run_out() -> None:
    kept = KeptPhotos(max_bytes=2500, max_seconds=60, clock=lambda: 0.0)
    reads = Reads(size=1000)
    for version in (1, 2, 3):
        kept.get(("s", "starter", version), reads)
    kept.get(("s", "starter", 3), reads)
    kept.get(("s", "starter", 2), reads)
    assert reads.count == 3
    kept.get(("s", "starter", 1), reads)  # gone: the first read, unused since
    assert reads.count == 4
    kept.get(("s", "starter", 2), reads)  # kept: used after 3, which made room for 1
    assert reads.count == 4
    kept.get(("s", "starter", 3), reads)
    assert reads.count == 5
    kept.get(("s", "starter", 1), reads)  # gone for 3: 2 was used after it
    assert reads.count == 6
    assert kept.get(("s", "starter", 9), Reads(size=3000)) is not None  # too big: not kept
    assert kept.get(("s", "starter", 9), reads) is not None
    assert reads.count == 7


def test_no_photo_is_not_kept() -> None:
    kept = KeptPhotos()
    assert kept.get(("s", "starter", 1), lambda: None) is None
    assert kept.get(("s", "starter", 1), Reads()) is not None


def tap_landmarks(starter: Phone) -> None:
    """The starter taps five landmarks."""
    s = scene(5)
    starter.tapped(landmarks=landmarks(s.landmarks1), friend=s.epipole1)


def test_a_crop_shows_the_photo_as_it_now_is(uploaded: Phones) -> None:
    starter, joiner = uploaded
    tap_landmarks(starter)

    def crop() -> np.ndarray:
        return decode_photo(joiner.ok("GET", "/landmarks/starter/2/crop").content).astype(int)

    before = crop()
    assert np.array_equal(crop(), before)  # kept, the same
    white = encode_image(np.full((480, 640, 3), 255, np.uint8), format="png")
    assert starter.upload(white, "white.png").status_code == 200
    tap_landmarks(starter)
    after = crop()
    assert after[100:140, :60].min() >= 240  # the new, white photo, not the one kept
    assert np.abs(before[100:140, :60] - 255).max() > 40


def test_a_photo_replaced_since_the_snapshot_is_not_kept_under_the_old_name(
    services: Services, uploaded: Phones, temple_photos: tuple[bytes, bytes]
) -> None:
    starter = uploaded[0]
    store: Photos = services.pictures.photos
    old = services.answers.snapshot(starter.session_id).photos["starter"].version
    assert old is not None
    assert starter.upload(temple_photos[1], "again.png").status_code == 200
    assert store.get(starter.session_id, "starter", old) is None  # read after the snapshot
    new = services.answers.snapshot(starter.session_id).photos["starter"].version
    kept = store.get(starter.session_id, "starter", new)
    assert kept is not None
    assert new != old
    assert store.get(starter.session_id, "starter", new) is kept


def test_after_delete_now_no_crop_is_served(client: TestClient, uploaded: Phones) -> None:
    starter, joiner = uploaded
    tap_landmarks(starter)
    url = joiner.url("/landmarks/starter/2/crop")
    assert client.get(url, headers=joiner.auth).status_code == 200  # now kept
    assert joiner.call("DELETE").status_code == 204
    gone = client.get(url, headers=joiner.auth)
    assert gone.status_code in (401, 404), gone.text
    assert gone.headers["content-type"].startswith("application/json")
