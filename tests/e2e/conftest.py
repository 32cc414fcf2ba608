"""Phones against a real server on loopback: Debian's Chromium (Playwright) and Debian's
WebKitGTK (Selenium and WebKitWebDriver), behind one :class:`phone.Phone`.

A test that takes the ``pixel`` and ``iphone`` phones runs in Chromium; marked
``@pytest.mark.engines("chromium", "webkit")`` (or the module's ``pytestmark``) it runs once
per engine, both phones in that engine.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Generator, Iterator
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import TypeVar

import httpx2
import pytest
from chromium_pool import ChromiumPool
from playwright.sync_api import Browser, Playwright, sync_playwright
from webkit_pool import Kind, WebKitPool

from deploy.replica import serve
from testbed import chromium
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.browser.phone import Phone
from testbed.browser.webkit_phone import Screen

ROOT = Path(__file__).parents[2]
# A venue-like name for loopback (browsers treat "localhost" and 127.0.0.1 as secure even
# over plain HTTP; a phone on the LAN gets no such favour): tests/e2e/test_https.py.
VENUE_NAME = "--host-resolver-rules=MAP buddy.test 127.0.0.1"
# The in-app camera: Chromium's fake camera (a test pattern) and no permission prompt.
FAKE_CAMERA = ("--use-fake-device-for-media-stream", "--use-fake-ui-for-media-stream")
SCREENSHOTS = ROOT / "artifacts" / "screenshots"
ENGINES = ("chromium", "webkit")
P = TypeVar("P", bound=Phone)
# Each test's reports (setup, call, teardown), for its phones' teardown.
REPORTS = pytest.StashKey[dict[str, pytest.TestReport]]()


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    """``engine``: the engines the test's ``engines`` marker names, else Chromium."""
    if "engine" in metafunc.fixturenames:
        marker = metafunc.definition.get_closest_marker("engines")
        engines = marker.args if marker else ("chromium",)
        assert set(engines) <= set(ENGINES), engines
        metafunc.parametrize("engine", engines)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(
    item: pytest.Item,
) -> Generator[None, pytest.TestReport, pytest.TestReport]:
    """Keep the report on the test: a WebKit phone is reused only after a passed test."""
    report = yield
    item.stash.setdefault(REPORTS, {})[report.when] = report
    return report


@pytest.fixture(scope="session")
def playwright() -> Iterator[Playwright]:
    with sync_playwright() as running:
        yield running


@pytest.fixture(scope="session")
def browser(playwright: Playwright) -> Iterator[Browser]:
    assert (ROOT / "frontend" / "dist" / "index.html").is_file(), "build the app: make test does"
    launched = chromium.launch(playwright, (VENUE_NAME, *FAKE_CAMERA))
    yield launched
    launched.close()


@pytest.fixture(scope="session")
def chromium_pool(playwright: Playwright, browser: Browser, server: str) -> Iterator[ChromiumPool]:
    """This worker's Chromium contexts, kept from test to test, their keeper pages on the
    worker's server (chromium_pool.py)."""
    pool = ChromiumPool(playwright, browser, f"{server}/icon-192.png")
    yield pool
    pool.close()


@pytest.fixture(scope="session")
def webkit_pool(tmp_path_factory: pytest.TempPathFactory) -> Iterator[WebKitPool]:
    """This worker's WebKit phones, kept from test to test (webkit_pool.py)."""
    pool = WebKitPool(tmp_path_factory.mktemp("webkit"))
    yield pool
    pool.close()


@pytest.fixture(scope="session")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """One server per pytest worker for the tests that need a plain one: each test starts
    searches of its own, which no other sees, and uvicorn takes 2-4 s to start (about 40
    starts saved per run). A test that stops, cuts or configures its server starts its own
    (``deploy.replica.serve``)."""
    with serve(tmp_path_factory.mktemp("server")) as running:
        yield running.base_url


@pytest.fixture
def api(server: str) -> Iterator[httpx2.Client]:
    """The worker's server as a script calls it: the client of ``testbed.client`` (a
    starter's calls from ``testbed.client.start``)."""
    with httpx2.Client(base_url=server, timeout=30) as client:
        yield client


def unexpected(errors: list[str], request: pytest.FixtureRequest) -> list[str]:
    """The errors but those the test expects (``@pytest.mark.expected_console_errors``:
    Chromium logs every 4xx answer to a fetch, a refused join code among them)."""
    marker = request.node.get_closest_marker("expected_console_errors")
    if marker is None:
        return errors
    return [error for error in errors if not re.search(marker.args[0], error)]


def screen(playwright: Playwright, model: str) -> Screen:
    """The screen of Playwright's descriptor of ``model``: the same size in both engines."""
    device = playwright.devices[model]
    viewport, whole = device["viewport"], device["screen"]
    return Screen(
        viewport=(viewport["width"], viewport["height"]),
        screen=(whole["width"], whole["height"]),
        scale=device["device_scale_factor"],
    )


def phone(
    engine: str,
    model: str,
    playwright: Playwright,
    request: pytest.FixtureRequest,
    browser: Browser | None = None,
) -> Iterator[Phone]:
    """A phone of ``model`` in ``engine`` (in Chromium, a new context of ``browser``, else a
    page in a context of the worker's pool; in WebKit, one of the worker's pool; what a pool
    lent is given back after the test, and kept if it passed); the test fails if its page
    reported errors."""
    if engine == "chromium" and browser is not None:
        yield from closed_after(ChromiumPhone(playwright, browser, model), request)
        return
    if engine == "chromium":
        contexts: ChromiumPool = request.getfixturevalue("chromium_pool")
        kept = contexts.take(model)
        started = ChromiumPhone(playwright, contexts.browser, model, context=kept.context)

        def give_back(passed: bool) -> None:
            reuse = passed and not started.beyond_the_page
            contexts.give_back(model, kept, started.origins, reuse=reuse)

        yield from _lent(started, give_back, request)
        return
    turns = request.node.get_closest_marker("turns") is not None
    shown = screen(playwright, model)
    if request.node.get_closest_marker("device_pixels") is None:
        # The model's CSS viewport at one device pixel per CSS pixel: WebKitGTK rasterises
        # every frame on the CPU here, and the iPhone's 3x cost the WebKit tests 30 % of
        # their CPU (test_two_phones: 69 core-s at 1x, 98 at 3x). What the engine does with
        # a page is the same; the app reads the ratio only for its loupe's canvas.
        shown = dataclasses.replace(shown, scale=1.0)
    kind: Kind = (model, shown, turns)
    pool: WebKitPool = request.getfixturevalue("webkit_pool")
    taken = pool.take(kind)
    yield from _lent(taken, lambda passed: pool.give_back(kind, taken, reuse=passed), request)


def _lent(
    started: P, give_back: Callable[[bool], None], request: pytest.FixtureRequest
) -> Iterator[P]:
    """``started`` for the test; then ``give_back(passed)``: whether the test passed and its
    pages reported no error it did not expect (the test fails if they did)."""
    found: list[str] | None = None
    try:
        yield started
        found = unexpected(started.console_errors(), request)
    finally:
        call = request.node.stash.get(REPORTS, {}).get("call")
        give_back(found == [] and call is not None and call.passed)
    assert found == [], f"the {started}'s pages reported errors"


def closed_after(started: P, request: pytest.FixtureRequest) -> Iterator[P]:
    """``started`` for the test, then closed; the test fails if its pages reported errors
    it did not expect."""
    yield from _lent(started, lambda _: started.close(), request)


@pytest.fixture
def pixel(engine: str, playwright: Playwright, request: pytest.FixtureRequest) -> Iterator[Phone]:
    yield from phone(engine, "Pixel 7", playwright, request)


@pytest.fixture
def iphone(engine: str, playwright: Playwright, request: pytest.FixtureRequest) -> Iterator[Phone]:
    yield from phone(engine, "iPhone 13", playwright, request)


@pytest.fixture
def filming(
    playwright: Playwright, request: pytest.FixtureRequest, tmp_path: Path
) -> Iterator[Callable[[Path], Phone]]:
    """Makes Pixel 7s in Chromium whose camera films a video: ``filming(video)`` for a
    YUV4MPEG2 file (testbed/y4m.py). The file is a flag of the browser, so each phone is a
    Chromium of its own; all are closed after the test."""
    with ExitStack() as stack:

        def film(video: Path) -> Phone:
            flags = (VENUE_NAME, *FAKE_CAMERA, f"--use-file-for-fake-video-capture={video}")
            launched = chromium.launch(playwright, flags)
            stack.callback(launched.close)
            managed = contextmanager(phone)
            return stack.enter_context(
                managed("chromium", "Pixel 7", playwright, request, launched)
            )

        yield film


@pytest.fixture
def screenshots(engine: str) -> Path:
    """Chromium's screenshots (the README's) in artifacts/screenshots, WebKit's in its
    webkit/ folder."""
    folder = SCREENSHOTS if engine == "chromium" else SCREENSHOTS / engine
    folder.mkdir(parents=True, exist_ok=True)
    return folder
