"""The installed app (issue 25): its manifest, a reload with no signal, and a new build.

Chromium only (the DevTools protocol): the one browser context here that lets the app's
service worker run (every other test's blocks it: testbed/chromium.py).

No signal is Playwright's ``context.set_offline(True)``, which emulates it through the
DevTools protocol (``Network.emulateNetworkConditions``) for the page *and* for the
service worker: a phone with no signal has neither. (A CDP session of the page alone, as
test_catch_up.py uses, leaves the worker's own requests online: the test checks that the
worker's fetches fail too.)
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx2
import pytest
from chromium_phone import ChromiumPhone
from conftest import unexpected
from phone import Phone, expect
from playwright.sync_api import Browser, Playwright
from test_two_phones import (
    PAIR,
    mark_friend,
    scene,
    session_state,
    start_and_join,
    tap_landmark,
    tap_landmarks,
    temple,
    upload,
)

from deploy.replica import serve

ROOT = Path(__file__).parents[2]
FRONTEND = ROOT / "frontend"
# While offline, the page's API requests fail and Chromium says so.
DROPPED = r"Failed to load resource|ERR_INTERNET_DISCONNECTED"


@pytest.fixture
def installed(
    playwright: Playwright, browser: Browser, request: pytest.FixtureRequest
) -> Iterator[ChromiumPhone]:
    """A Pixel 7 whose browser runs the app's service worker; the test fails if its pages
    reported errors."""
    phone = ChromiumPhone(playwright, browser, "Pixel 7", service_workers=True)
    try:
        yield phone
        errors = phone.console_errors()
    finally:
        phone.close()
    assert unexpected(errors, request) == [], "the installed phone's pages reported errors"


def worker_ready(phone: ChromiumPhone) -> None:
    """The app's worker is active (its precache complete) and controls the page."""
    phone.wait_for(
        lambda: phone.evaluate(
            """async () => {
                const registration = await navigator.serviceWorker.getRegistration();
                return registration?.active?.state === "activated";
            }"""
        ),
        "the service worker to be active",
    )


def worker_fetch(phone: ChromiumPhone, path: str) -> Any:
    """What the service worker itself gets for ``path`` (a status, or "failed")."""
    (worker,) = phone.context.service_workers
    return worker.evaluate(f"fetch({path!r}).then((r) => r.status, () => 'failed')")


@pytest.mark.expected_console_errors(DROPPED)
def test_a_reload_with_no_signal_shows_the_session_and_its_taps(
    server: str, installed: ChromiumPhone, iphone: Phone
) -> None:
    starter, _ = start_and_join(server, installed, iphone)
    upload(starter, temple(PAIR[0]))
    truth = scene(3, seed=25)
    mark_friend(starter, *truth.epipole1)
    tap_landmarks(starter, truth.landmarks1[:2])
    worker_ready(starter)

    installed.context.set_offline(True)
    assert worker_fetch(installed, "/healthz") == "failed"
    reloaded = installed.page.reload()
    assert reloaded is not None
    assert reloaded.from_service_worker
    # The shell from the worker; the session from the phone: its photo's frame, the friend
    # and both landmarks, and a plain "Offline" instead of an error.
    expect(starter.get_by_test_id("offline")).to_have_text("Offline")
    expect(starter.get_by_test_id("photo-view")).to_have_attribute("data-photo-width", "640")
    expect(starter.locator('[data-testid="landmark"]')).to_have_count(2)
    expect(starter.get_by_test_id("friend-mark")).to_be_visible()
    expect(starter.get_by_test_id("photo-loading")).to_contain_text("back online")
    # A tap with no signal is kept.
    tap_landmark(starter, 3, truth.landmarks1[2])
    expect(starter.get_by_test_id("save-state")).not_to_have_attribute("data-state", "saved")

    installed.context.set_offline(False)
    expect(starter.get_by_test_id("offline")).to_have_count(0)
    expect(starter.get_by_test_id("peer-online")).to_have_attribute("data-online", "true")
    expect(starter.get_by_test_id("save-state")).to_have_attribute("data-state", "saved")
    expect(starter.get_by_test_id("photo-loading")).to_have_count(0)
    ids = sorted(t["id"] for t in session_state(starter)["taps"]["starter"]["landmarks"])
    assert ids == [1, 2, 3]


@contextmanager
def building(version: str, folder: Path) -> Iterator[Callable[[], set[str]]]:
    """The app built as ``version`` into ``folder``, in the background (vite build takes
    2-20 s on a busy machine, as long as a server's start): the function it yields waits
    for the build and gives its files' paths (``/assets/...``)."""
    command = ["npx", "vite", "build", "--outDir", str(folder), "--emptyOutDir"]
    environment = os.environ | {"VITE_APP_VERSION": version}
    with subprocess.Popen([*command, "--logLevel", "warn"], cwd=FRONTEND, env=environment) as vite:

        def built() -> set[str]:
            assert vite.wait(timeout=120) == 0, "vite build failed"
            return files(folder)

        yield built


def files(folder: Path) -> set[str]:
    return {"/" + str(path.relative_to(folder)) for path in folder.rglob("*") if path.is_file()}


def scripts(phone: ChromiumPhone) -> set[str]:
    """The path of every script the page loaded (its entry and every chunk since)."""
    loaded: list[str] = phone.evaluate(
        """() => [
            ...[...document.scripts].map((s) => s.src),
            ...performance.getEntriesByType("resource")
              .filter((e) => e.name.endsWith(".js")).map((e) => e.name),
        ].filter(Boolean).map((url) => new URL(url).pathname)"""
    )
    return set(loaded)


def cached(phone: ChromiumPhone) -> set[str]:
    """The path of everything in the page's caches (the worker's precache)."""
    paths: list[str] = phone.evaluate(
        """async () => {
            const paths = [];
            for (const name of await caches.keys()) {
                const cache = await caches.open(name);
                for (const request of await cache.keys()) paths.push(new URL(request.url).pathname);
            }
            return paths;
        }"""
    )
    return set(paths)


def test_a_new_build_replaces_the_whole_shell(installed: ChromiumPhone, tmp_path: Path) -> None:
    """Build A served and installed; the server then has build B: a reload runs B only."""
    dist = tmp_path / "dist"
    shutil.copytree(FRONTEND / "dist", dist)
    version = f"b-{os.getpid()}"
    with (
        building(version, tmp_path / "b") as built,
        serve(tmp_path, env={"BUDDY_FRONTEND_DIR": str(dist)}) as server,
    ):
        installed.goto(f"{server.base_url}/")
        expect(installed.get_by_test_id("start")).to_be_visible()
        worker_ready(installed)
        old_scripts = scripts(installed)
        assert old_scripts
        assert old_scripts <= files(dist)
        assert installed.evaluate("() => document.documentElement.dataset.build") != version

        new_build = built()
        shutil.rmtree(dist)
        shutil.copytree(tmp_path / "b", dist)
        # The open page of A still gets A's files, from A's precache: the server has no more.
        (entry,) = old_scripts - new_build
        assert httpx2.get(f"{server.base_url}{entry}").status_code == 404
        assert installed.evaluate(f"fetch({entry!r}).then((r) => r.status)") == 200

        installed.reload()  # A's shell, from A's worker: it finds B and moves to it
        installed.wait_for(
            lambda: installed.evaluate("() => document.documentElement.dataset.build") == version,
            "the page to run build B",
        )
        expect(installed.get_by_test_id("start")).to_be_visible()
        loaded = scripts(installed)
        assert loaded
        assert loaded <= new_build, loaded - new_build
        in_cache = cached(installed)
        assert "/index.html" in in_cache
        assert in_cache <= new_build, in_cache - new_build
        assert installed.evaluate(
            """async () => {
                const registration = await navigator.serviceWorker.getRegistration();
                return registration.waiting === null && registration.installing === null;
            }"""
        )


def test_the_manifest_makes_the_app_installable(installed: ChromiumPhone, server: str) -> None:
    """Chromium's own reading of the manifest: no errors, and nothing keeps it from being
    installed (a service worker, icons of the right sizes, standalone)."""
    installed.goto(f"{server}/")
    worker_ready(installed)
    devtools = installed.context.new_cdp_session(installed.page)
    manifest = devtools.send("Page.getAppManifest", {})
    assert manifest["errors"] == [], manifest["errors"]
    # (The parsed manifest comes back in Chromium's own enum names: "kStandalone".)
    parsed = manifest["manifest"]
    assert parsed["name"] == "Buddy Search"
    assert parsed["display"] == "kStandalone"
    # Playwright's contexts are incognito ones, where Chromium installs nothing: the one
    # error there is of the browser, none of the app.
    errors = devtools.send("Page.getInstallabilityErrors")["installabilityErrors"]
    assert [error["errorId"] for error in errors] == ["in-incognito"], errors
