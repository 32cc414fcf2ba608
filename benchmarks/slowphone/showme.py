"""Show me's opening on a slow phone: from the tap on "Show me" to the first marker drawn over
the live video (the app's own performance marks, on the page's clock), with the CPU
throttled as the rest of the benchmark throttles it.

One phone per rate, in a Chromium of its own whose fake camera films the temple photo
(``--use-file-for-fake-video-capture``) and whose sensors the DevTools protocol holds
still, upright and level. It takes its photo with the in-app camera, so the view opens
anchored at the shutter and draws at once; a starter over the API marks it and taps three
landmarks of the temple scene, which the phone finds (its taps, unthrottled: what is
measured is the opening). Then the CPU is throttled, and "Show me" is opened and closed
``count`` times: the first opening fetches and compiles the view's code, the others find it
loaded. Not modelled: a phone's camera starting (Chromium's fake camera starts at this
machine's speed).
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import cv2
import httpx2
import numpy as np
from playwright.sync_api import Page, Playwright, expect

from testbed import chromium
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.client import numbered, start
from testbed.opening import FORGET, MARK_TAP, OPENED, OPENING_STEPS
from testbed.scenes import temple_scene
from testbed.y4m import write_y4m

from .play import MODEL, WAIT_MS

TEMPLE = Path(__file__).resolve().parents[2] / "tests" / "data" / "temple"
PAIR = ("templeSR0003", "templeSR0006")  # the starter's photo, the phone's (filmed)
SCENE_SEED = 12
LANDMARKS = 3
FILM = ("--use-fake-device-for-media-stream", "--use-fake-ui-for-media-stream")
# Held still, upright and level: the accelerometer's push against gravity up the screen
# (m/s^2), nothing else moving, and the orientation a quarter turn about x (beta 90 degrees).
UP = (0.0, 9.80665, 0.0)
UPRIGHT = (math.sin(math.pi / 4), 0.0, 0.0, math.cos(math.pi / 4))
# A phone's camera films at 30 frames a second: Chromium's fake camera delivers its first
# frame one frame's time after the stream starts.
CAMERA_FPS = 30
POLL_MS = 100  # how often the benchmark asks the page: polling every frame loads it


def _starter(http: httpx2.Client) -> tuple[str, np.ndarray]:
    """A search started over the API: the starter's photo, its mark of the phone and three
    landmarks. Its join code, and the landmarks' pixels in the phone's photo."""
    scene = temple_scene(
        TEMPLE / "templeSR_par.txt", *PAIR, LANDMARKS, np.random.default_rng(SCENE_SEED)
    )
    starter, code = start(http, TEMPLE / f"{PAIR[0]}.png")
    starter.tapped(friend=scene.epipole1, landmarks=numbered(scene.landmarks1))
    return code, scene.landmarks2


def _answered(page: Page, server: str) -> None:
    """The phone joins, photographs the temple in the app and finds the starter's landmarks:
    its answer, a point, is on the screen with "Show me"."""
    with httpx2.Client(base_url=server, timeout=30) as http:
        code, landmarks = _starter(http)
    page.goto(f"{server}/join/{code}")
    page.get_by_test_id("open-camera").tap()
    page.get_by_test_id("motion-allow").tap()
    expect(page.get_by_test_id("camera-note")).to_contain_text("Which way is down is known")
    expect(page.get_by_test_id("in-app-camera")).to_have_attribute("data-phase", "live")
    page.get_by_test_id("shutter").tap()
    expect(page.get_by_test_id("save-state")).to_have_attribute("data-state", "saved")
    page.get_by_test_id("cannot-see").tap()
    phone = ChromiumPhone.on(page, MODEL)
    phone.whole_photo()
    for number, (x, y) in enumerate(landmarks, 1):
        phone.tap_photo(x, y)
        expect(page.locator(f'[data-testid="landmark"][data-id="{number}"]')).to_be_visible()
    expect(page.get_by_test_id("show-me")).to_be_visible()


def openings(
    playwright: Playwright, server: str, rate: float, count: int
) -> list[dict[str, float]]:
    """``count`` openings of Show me at CPU ``rate`` on a fresh phone: each one's STEPS, ms
    after the tap, the last the first marker drawn over the live video (the first opening
    fetches the view's code)."""
    expect.set_options(timeout=WAIT_MS)
    with tempfile.TemporaryDirectory() as folder:
        film = Path(folder) / "temple.y4m"
        photo = cv2.imread(str(TEMPLE / f"{PAIR[1]}.png"), cv2.IMREAD_COLOR)
        write_y4m(film, [np.asarray(photo, np.uint8)], fps=CAMERA_FPS)
        flags = (*FILM, f"--use-file-for-fake-video-capture={film}")
        with chromium.launch(playwright, flags) as browser:
            context = chromium.phone(playwright, browser, MODEL)
            page = context.new_page()
            sensors = chromium.Sensors(context, page)
            sensors.hold_still(UP)
            sensors.hold_orientation(UPRIGHT)
            _answered(page, server)
            cdp = context.new_cdp_session(page)
            page.evaluate(MARK_TAP)
            cdp.send("Emulation.setCPUThrottlingRate", {"rate": rate})
            took = []
            for _ in range(count):
                page.evaluate(FORGET)
                page.get_by_test_id("show-me").tap()
                page.wait_for_function(OPENED, polling=POLL_MS)
                took.append({k: float(v) for k, v in page.evaluate(OPENING_STEPS).items()})
                page.get_by_test_id("live-close").tap()
                expect(page.get_by_test_id("live-view")).to_have_count(0)
            return took
