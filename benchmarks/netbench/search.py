"""One search on two phones in Chromium, as a person would make it, on one network profile.

The starter (a Pixel 7) can see the joiner (an iPhone 13); the joiner cannot see the
starter. Both pick a 12 MP photo of a rendered hall (:func:`hall_photos`). The joiner taps
its landmarks as soon as its photo is on screen; the starter marks the joiner, then finds
the same landmarks; its last tap gives the joiner's phone a new answer: where the starter
is, drawn on the joiner's photo.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from playwright.sync_api import Browser, BrowserContext, Page, Playwright, expect

from shared_solver.projective import Array
from testbed import chromium
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.venue import rendered_pair

from .meter import Meter, Profile
from .watch import INIT, WATCH_ANSWER, stamps

# A phone's main camera: 12 MP, 4032 px on the long side; the app sends it at 2560 px.
ORIGINAL_SIDE = 4032
ORIGINAL_QUALITY = 92
# Spots a person taps on the whole photo are apart on the screen (benchmarks/taps.py): no
# two taps of a photo closer than this fraction of its diagonal, none near its edges.
APART = 0.1
MARGIN = 0.05
WAIT_MS = 60_000
CLOCKS_MS = 50.0


@dataclass(frozen=True)
class Photos:
    """The two phones' photos (their original files) and where to tap, in stored pixels."""

    original1: Path
    original2: Path
    landmarks1: Array  # (K, 2)
    landmarks2: Array  # (K, 2)
    friend2: Array  # (2,): the joiner in photo 1, which the starter marks


@dataclass(frozen=True)
class PhoneRun:
    tappable_ms: float
    uploaded_ms: float
    sent: int
    received: int
    by_kind: dict[str, int]


@dataclass(frozen=True)
class SearchRun:
    profile: str
    starter: PhoneRun
    joiner: PhoneRun
    answer_text_ms: float
    answer_drawn_ms: float
    # Where that time went: the tap to its PUT leaving the starter, the PUT in the app (its
    # Server-Timing), its leaving to the answer's event reaching the joiner, that event to
    # the answer drawn.
    tap_to_sent_ms: float
    server_ms: float
    sent_to_event_ms: float
    event_to_drawn_ms: float


def hall_photos(folder: Path, seed: int, landmarks: int) -> Photos:
    """A rendered hall with ``landmarks`` spots far enough apart in both photos, its photos
    enlarged to a 12 MP phone's and saved as its JPEGs (EXIF-less: the lens is assumed)."""
    for attempt in range(100):
        pair = rendered_pair([seed, attempt])
        scene = pair.scene
        chosen = _spread(
            [scene.landmarks1, scene.landmarks2],
            [pair.photo1.shape[1::-1], pair.photo2.shape[1::-1]],
            scene.epipole1,
            landmarks,
        )
        if chosen is None:
            continue
        paths = []
        for index, photo in ((1, pair.photo1), (2, pair.photo2)):
            height, width = photo.shape[:2]
            factor = ORIGINAL_SIDE / max(width, height)
            size = (round(width * factor), round(height * factor))
            original = cv2.resize(photo, size, interpolation=cv2.INTER_CUBIC)
            path = folder / f"hall{index}.jpg"
            cv2.imwrite(str(path), original, [cv2.IMWRITE_JPEG_QUALITY, ORIGINAL_QUALITY])
            paths.append(path)
        return Photos(
            paths[0],
            paths[1],
            scene.landmarks1[chosen],
            scene.landmarks2[chosen],
            np.asarray(scene.epipole1, dtype=np.float64),
        )
    raise RuntimeError(f"no hall of seed {seed} has {landmarks} landmarks apart")


def _spread(
    points: list[Array], sizes: list[tuple[int, int]], friend: Array, count: int
) -> list[int] | None:
    """Indices of ``count`` landmarks apart in every photo (and from the friend in photo 1)."""
    chosen: list[int] = []
    for i in range(len(points[0])):
        fits = True
        for which, (pts, (w, h)) in enumerate(zip(points, sizes, strict=True)):
            x, y = pts[i]
            if not (MARGIN * w < x < (1 - MARGIN) * w and MARGIN * h < y < (1 - MARGIN) * h):
                fits = False
            others = [pts[j] for j in chosen] + ([friend] if which == 0 else [])
            if any(np.hypot(*(pts[i] - q)) < APART * np.hypot(w, h) for q in others):
                fits = False
        if fits:
            chosen.append(i)
        if len(chosen) == count:
            return chosen
    return None


def _phone(
    browser: Browser, playwright: Playwright, model: str, profile: Profile
) -> tuple[BrowserContext, Page, Meter]:
    context: BrowserContext = chromium.phone(playwright, browser, model)
    context.add_init_script(INIT)
    page = context.new_page()
    meter = Meter(profile)
    meter.attach(context, page)
    return context, page, meter


def saved(page: Page) -> None:
    expect(page.get_by_test_id("save-state")).to_have_attribute("data-state", "saved")


def _landmark(page: Page, number: int) -> None:
    expect(page.locator(f'[data-testid="landmark"][data-id="{number}"]')).to_be_visible()


def _settled(*phones: tuple[Page, Meter]) -> None:
    """Until no phone has a request on its way."""
    deadline = time.monotonic() + WAIT_MS / 1000
    while True:
        for page, _ in phones:
            page.evaluate("() => 0")  # Playwright delivers the protocol's events meanwhile
        waiting = [path for _, meter in phones for path in meter.waiting()]
        if not waiting:
            return
        if time.monotonic() > deadline:
            raise TimeoutError(f"requests still on their way: {waiting}")
        time.sleep(0.05)


def play(
    browser: Browser, playwright: Playwright, server: str, profile: Profile, photos: Photos
) -> SearchRun:
    """One search on ``profile`` (both phones on it), measured."""
    expect.set_options(timeout=WAIT_MS)
    starter_context, starter, starter_meter = _phone(browser, playwright, "Pixel 7", profile)
    joiner_context, joiner, joiner_meter = _phone(browser, playwright, "iPhone 13", profile)
    with starter_context, joiner_context:
        starter.goto(f"{server}/")
        starter.get_by_test_id("start").tap()
        code = starter.get_by_test_id("code")
        expect(code).to_have_text(re.compile(r"^\s*\d{4}\s?\d{4}\s*$"))
        digits = re.sub(r"\D", "", code.inner_text())
        joiner.goto(f"{server}/join/{digits}")  # the join link, opened on the friend's phone
        for page in (starter, joiner):
            expect(page.get_by_test_id("photo-input")).to_be_attached()
            expect(page.locator(".photo-step")).to_be_visible()
        starter.get_by_test_id("photo-input").set_input_files(photos.original1)
        joiner.get_by_test_id("photo-input").set_input_files(photos.original2)
        for page in (starter, joiner):
            page.wait_for_function("() => window.__bench.tappable !== null", timeout=WAIT_MS)
        starting, joining = (
            ChromiumPhone.on(starter, "Pixel 7"),
            ChromiumPhone.on(joiner, "iPhone 13"),
        )
        for phone in (starting, joining):
            phone.whole_photo()

        # The joiner taps at once, its upload still on its way.
        joiner.get_by_test_id("cannot-see").tap()
        for number, point in enumerate(photos.landmarks2, 1):
            joining.tap_photo(*point)
            _landmark(joiner, number)

        expect(starter.get_by_test_id("friend-prompt")).to_be_visible()
        starting.tap_photo(*photos.friend2)
        expect(starter.get_by_test_id("friend-mark")).to_be_visible()
        last = len(photos.landmarks1)
        for number, point in enumerate(photos.landmarks1, 1):
            expect(starter.get_by_test_id("find-prompt")).to_have_attribute("data-id", str(number))
            if number == last:
                # Both settled, as after a person's look at the screen: the answer before
                # the last tap drawn, no request on its way (a suggested spot searched for
                # the last landmark, say: it takes the server's CPU from the answer's).
                saved(starter)
                expect(joiner.get_by_test_id("result-position")).to_be_visible()
                expect(joiner.locator("img.preload")).to_have_count(0)
                _settled((starter, starter_meter), (joiner, joiner_meter))
                joiner.evaluate(WATCH_ANSWER)
            starting.tap_photo(*point)
            _landmark(starter, number)
        joiner.wait_for_function(
            "() => window.__bench.text !== null && window.__bench.drawn !== null", timeout=WAIT_MS
        )
        for page in (starter, joiner):
            saved(page)
            page.wait_for_function("() => window.__bench.uploaded !== null", timeout=WAIT_MS)
        answer = stamps(joiner)
        tapped = stamps(starter)["lifted"]  # the last tap placed, as the finger lifts
        runs = [
            _phone_run(page, meter)
            for page, meter in ((starter, starter_meter), (joiner, joiner_meter))
        ]
        # The page's and the protocol's clocks may differ by a millisecond or two; the PUT
        # before this one left seconds earlier.
        put = starter_meter.first_sent("PUT", "/taps", tapped - CLOCKS_MS)
        told = joiner_meter.first_event("answer", put.sent_at)
        return SearchRun(
            profile.name,
            runs[0],
            runs[1],
            answer["text"] - tapped,
            answer["drawn"] - tapped,
            tap_to_sent_ms=put.sent_at - tapped,
            server_ms=put.server_ms or float("nan"),
            sent_to_event_ms=told - put.sent_at,
            event_to_drawn_ms=answer["drawn"] - told,
        )


def _phone_run(page: Page, meter: Meter) -> PhoneRun:
    stamp = stamps(page)
    sent, received = meter.totals()
    return PhoneRun(
        stamp["tappable"] - stamp["chosen"],
        stamp["uploaded"] - stamp["chosen"],
        sent,
        received,
        meter.by_kind(),
    )
