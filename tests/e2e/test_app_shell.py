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
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx2
import pytest
from conftest import closed_after
from playwright.sync_api import Browser, Playwright

from deploy.replica import serve
from testbed.browser import play
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.browser.phone import Phone, expect

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
    yield from closed_after(phone, request)


def worker_ready(phone: ChromiumPhone) -> None:
    """The app's worker is active (its precache complete) and controls the page."""
    phone.wait_for(
        lambda: phone.evaluate(
            """async () => {
                const registration = await navigator.serviceWorker.getRegistration();
                return registration?.active?.state === "activated"
                    && navigator.serviceWorker.controller !== null;
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
    shell_server: ShellServer, installed: ChromiumPhone, iphone: Phone
) -> None:
    starter, _ = play.start_and_join(shell_server.base_url, installed, iphone)
    play.upload(starter, play.temple(play.PAIR[0]))
    truth = play.scene(3, seed=25)
    play.mark_friend(starter, *truth.epipole1)
    play.tap_landmarks(starter, truth.landmarks1[:2])
    worker_ready(installed)  # the starter

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
    play.tap_landmark(starter, 3, truth.landmarks1[2])
    expect(starter.get_by_test_id("save-state")).not_to_have_attribute("data-state", "saved")

    installed.context.set_offline(False)
    expect(starter.get_by_test_id("offline")).to_have_count(0)
    expect(starter.get_by_test_id("peer-online")).to_have_attribute("data-online", "true")
    expect(starter.get_by_test_id("save-state")).to_have_attribute("data-state", "saved")
    expect(starter.get_by_test_id("photo-loading")).to_have_count(0)
    ids = sorted(t["id"] for t in play.session_state(starter)["taps"]["starter"]["landmarks"])
    assert ids == [1, 2, 3]
    # The worker kept the build's files and nothing else: no state, no photo, no crop.
    in_cache = cached(installed)
    assert in_cache
    assert in_cache <= files(shell_server.dist), in_cache - files(shell_server.dist)


def test_the_manifest_makes_the_app_installable(
    installed: ChromiumPhone, shell_server: ShellServer
) -> None:
    """Chromium's own reading of the manifest: no errors, and nothing keeps it from being
    installed (a service worker, icons of the right sizes, standalone)."""
    installed.goto(f"{shell_server.base_url}/")
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


@dataclass(frozen=True)
class Build:
    version: str
    folder: Path


@dataclass(frozen=True)
class ShellServer:
    """A server of the checked-out build (A) in ``dist``, and a new build (B) on its way:
    ``new_build()`` waits for it."""

    base_url: str
    dist: Path
    new_build: Callable[[], Build]


@pytest.fixture(scope="module")
def shell_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[ShellServer]:
    """This module's server, whose build the version bump replaces, and B's build, started
    at once: vite build took 12 to 23 s here on a busy machine, about as long as a server's
    start and the tests before the version bump, which run meanwhile."""
    folder = tmp_path_factory.mktemp("shell")
    dist, b_dist = folder / "dist", folder / "b"
    shutil.copytree(FRONTEND / "dist", dist)
    version = f"b-{os.getpid()}"
    command = ["npx", "vite", "build", "--outDir", str(b_dist), "--emptyOutDir"]
    environment = os.environ | {"VITE_APP_VERSION": version}
    with (
        subprocess.Popen([*command, "--logLevel", "warn"], cwd=FRONTEND, env=environment) as vite,
        serve(folder, env={"BUDDY_FRONTEND_DIR": str(dist)}) as server,
    ):

        def new_build() -> Build:
            assert vite.wait(timeout=120) == 0, "vite build failed"
            return Build(version, b_dist)

        yield ShellServer(server.base_url, dist, new_build)


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


def test_a_new_build_replaces_the_whole_shell(
    installed: ChromiumPhone, shell_server: ShellServer
) -> None:
    """Build A (the checked-out one) served and installed; the server then has build B: a
    reload runs B only."""
    server, dist = shell_server, shell_server.dist
    installed.goto(f"{server.base_url}/")
    expect(installed.get_by_test_id("start")).to_be_visible()
    worker_ready(installed)
    old_scripts = scripts(installed)
    assert old_scripts
    assert old_scripts <= files(dist)
    b = server.new_build()
    assert installed.evaluate("() => document.documentElement.dataset.build") != b.version

    shutil.rmtree(dist)
    shutil.copytree(b.folder, dist)
    b_files = files(dist)
    # The open page of A still gets A's files, from A's precache: the server has no more.
    (entry,) = old_scripts - b_files
    assert httpx2.get(f"{server.base_url}{entry}").status_code == 404
    assert installed.evaluate(f"fetch({entry!r}).then((r) => r.status)") == 200

    installed.reload()  # A's shell, from A's worker: it finds B and moves to it
    installed.wait_for(
        lambda: installed.evaluate("() => document.documentElement.dataset.build") == b.version,
        "the page to run build B",
    )
    expect(installed.get_by_test_id("start")).to_be_visible()
    loaded = scripts(installed)
    assert loaded
    assert loaded <= b_files, loaded - b_files
    in_cache = cached(installed)
    assert "/index.html" in in_cache
    assert in_cache <= b_files, in_cache - b_files
    assert installed.evaluate(
        """async () => {
            const registration = await navigator.serviceWorker.getRegistration();
            return registration.waiting === null && registration.installing === null;
        }"""
    )
