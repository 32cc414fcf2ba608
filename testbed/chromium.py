"""Debian's Chromium as the browser tests and the browser benchmarks launch it (`make test`
and `make browser` install the package when missing): no sandbox (root in CI), no GPU, and
nothing that would reach the internet."""

from __future__ import annotations

from typing import Any

CHROMIUM = "/usr/bin/chromium"
FLAGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def launch(playwright: Any, extra: tuple[str, ...] = ()) -> Any:
    """A headless Chromium browser of ``playwright`` (a ``sync_playwright()`` object)."""
    return playwright.chromium.launch(executable_path=CHROMIUM, args=[*FLAGS, *extra])


def phone(playwright: Any, browser: Any, model: str, *, service_workers: bool = False) -> Any:
    """A new context of ``browser`` emulating Playwright's phone ``model`` (viewport, device
    scale, touch, user agent), speaking English: the app picks the phone's language, and the
    tests read its English words (tests/e2e/test_languages.py sets the others itself).

    The app's service worker (its shell, offline) is blocked unless ``service_workers``:
    Playwright's routes do not see what a worker answers, and tests and benchmarks that
    play network faults or time requests should meet the server, as before the worker.
    tests/e2e/test_app_shell.py runs with it."""
    device = dict(playwright.devices[model])
    device.pop("default_browser_type", None)
    workers = "allow" if service_workers else "block"
    return browser.new_context(**{"locale": "en-US", **device}, service_workers=workers)


# The permissions the page needs for each sensor's readings (the orientation ones fuse the
# motion sensors, and the magnetometer for the compass).
_MOTION = ["accelerometer", "gyroscope"]
PERMISSIONS = {
    "accelerometer": _MOTION,
    "linear-acceleration": _MOTION,
    "gyroscope": _MOTION,
    "relative-orientation": [*_MOTION, "magnetometer"],
    "absolute-orientation": [*_MOTION, "magnetometer"],
}


class Sensors:
    """A page's sensors held by the test or benchmark: Chromium's sensor emulation (the
    DevTools protocol's ``Emulation.setSensorOverrideEnabled``/``setSensorOverrideReadings``)
    on a DevTools session of its own, each sensor turned on once (a second time is an error).
    Chromium hands the override to sensors the page starts after it, and sends a reading when
    it changes: hold a sensor before the page listens, then again to change it.

    ``context`` and ``page``: Playwright's; the context is granted each sensor's permissions
    as it is first held (:data:`PERMISSIONS`).
    """

    def __init__(self, context: Any, page: Any) -> None:
        self._context = context
        self._cdp = context.new_cdp_session(page)
        self._on: set[str] = set()

    def hold(self, sensor: str, reading: dict[str, Any]) -> None:
        """``sensor`` (``accelerometer``, ``relative-orientation``...) reads ``reading`` (the
        protocol's: ``{"xyz": {...}}`` or ``{"quaternion": {...}}``) from now on."""
        if sensor not in self._on:
            self._context.grant_permissions(PERMISSIONS[sensor])
            self._cdp.send("Emulation.setSensorOverrideEnabled", {"enabled": True, "type": sensor})
            self._on.add(sensor)
        self._cdp.send("Emulation.setSensorOverrideReadings", {"type": sensor, "reading": reading})

    def hold_xyz(self, sensor: str, xyz: tuple[float, float, float]) -> None:
        """A motion sensor's reading (m/s^2, rad/s): x right of the screen, y its top, z out."""
        self.hold(sensor, {"xyz": dict(zip("xyz", xyz, strict=True))})

    def hold_still(self, acceleration: tuple[float, float, float]) -> None:
        """The three sensors DeviceMotionEvent reads, of a phone held still: the accelerometer
        pushing back against gravity (``acceleration``), no linear acceleration, no turn."""
        self.hold_xyz("accelerometer", acceleration)
        self.hold_xyz("linear-acceleration", (0.0, 0.0, 0.0))
        self.hold_xyz("gyroscope", (0.0, 0.0, 0.0))

    def hold_orientation(
        self, quaternion: tuple[float, float, float, float], sensor: str = "relative-orientation"
    ) -> None:
        """An orientation sensor's reading: ``quaternion`` (x, y, z, w) turns the device frame
        into the earth's (x east, y north, z up; a relative sensor's own reference)."""
        self.hold(sensor, {"quaternion": dict(zip("xyzw", quaternion, strict=True))})
