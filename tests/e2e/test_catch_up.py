"""A phone that drops out catches up, in each engine: its network cut for 30 s in the middle
of a search while the other phone keeps tapping, its page hidden and shown again, the server
restarted. The phone keeps taking taps meanwhile; once it is back, both phones show the
same landmarks and the same answer as the server within 5 s, with no reload and no tap lost.

How the network is cut (docs/browsers.md): in Chromium, the DevTools protocol's offline
emulation (``Network.emulateNetworkConditions``); in WebKit, whose WebDriver has no network
emulation, the phone reaches the server through a loopback proxy the test cuts
(``testbed/browser/cutproxy.py``, through ``testbed.browser.link``).
"""

from __future__ import annotations

import math
import time
from contextlib import ExitStack
from pathlib import Path
from typing import Any

import pytest

from deploy.replica import free_port, serve
from testbed.browser import play
from testbed.browser.chromium_phone import ChromiumPhone
from testbed.browser.link import DROPPED, link
from testbed.browser.phone import Phone, expect

# Mostly waiting on the phones (make test runs them in a lane of their own).
pytestmark = pytest.mark.waits

OFFLINE_S = 30.0
CAUGHT_UP_S = 5.0


def midway(starter: Phone, joiner: Phone, s: Any, urls: tuple[str, str], found: int) -> None:
    """A search of scene ``s`` under way: the starter has marked its friend and landmarks 1-3,
    the joiner, who cannot see its friend, has found the first ``found`` (each phone at its
    address of ``urls``)."""
    play.start_and_join(urls[0], starter, joiner, joiner_server=urls[1], photos=True)
    play.marked_and_found(starter, joiner, s.epipole1, s.landmarks1[:3], s.landmarks2[:found])


def shown(phone: Phone) -> dict[str, Any]:
    """What the phone shows: its landmarks' numbers, the counter, the landmark it asks to
    find, whether its taps are saved, and the answer's position."""
    state: dict[str, Any] = phone.evaluate(
        """() => {
          const one = (id) => document.querySelector(`[data-testid="${id}"]`);
          const position = one("result-position");
          return {
            landmarks: [...document.querySelectorAll('[data-testid="landmark"]')]
              .map((l) => Number(l.dataset.id)).sort((a, b) => a - b),
            needed: one("next-step")?.dataset.needed ?? null,
            find: one("find-prompt")?.dataset.id ?? null,
            saved: one("save-state")?.dataset.state === "saved",
            friend: position ? [Number(position.dataset.x), Number(position.dataset.y)] : null,
          };
        }"""
    )
    return state


def ids(taps: dict[str, Any] | None) -> list[int]:
    return sorted(t["id"] for t in (taps or {}).get("landmarks", []))


def agrees(phone: Phone, server: dict[str, Any], role: str) -> bool:
    """Whether ``phone`` (playing ``role``) shows what the server has."""
    on_screen = shown(phone)
    answer = (server.get("answer") or {}).get("in_photo", {}).get(role) or {}
    friend = answer.get("friend")
    drawn = on_screen["friend"]
    same_answer = (friend is None and drawn is None) or (
        friend is not None
        and drawn is not None
        and all(math.isclose(a, b, abs_tol=1e-6) for a, b in zip(friend, drawn, strict=True))
    )
    return (
        on_screen["saved"]
        and on_screen["landmarks"] == ids(server["taps"][role])
        and on_screen["needed"] == str(server["landmarks_needed"])
        and same_answer
    )


def caught_up(starter: Phone, joiner: Phone, back: float, find: int | None) -> dict[str, Any]:
    """Wait until both phones show the server's state (the joiner asked to find ``find``),
    and check it took at most :data:`CAUGHT_UP_S` from ``back``; the server's state."""
    found: list[dict[str, Any]] = []

    def agreed() -> bool:
        state = play.session_state(starter)
        found[:] = [state]
        return (
            agrees(starter, state, "starter")
            and agrees(joiner, state, "joiner")
            and shown(joiner)["find"] == (None if find is None else str(find))
        )

    left = CAUGHT_UP_S - (time.monotonic() - back)
    try:
        starter.wait_for(agreed, "both phones to show the server's state", timeout=max(left, 0.1))
    except AssertionError as late:
        detail = {"starter": shown(starter), "joiner": shown(joiner), "server": found[:1]}
        raise AssertionError(f"{late}: {detail}") from None
    assert time.monotonic() - back <= CAUGHT_UP_S + 0.5
    return found[0]


def offline(joiner: Phone) -> None:
    """The joiner's phone knows it lost the server: its event stream is down."""
    expect(joiner.get_by_test_id("reconnecting")).to_be_visible()


@pytest.mark.engines("chromium", "webkit")
@pytest.mark.expected_console_errors(DROPPED)
def test_a_phone_offline_for_30_s_catches_up(pixel: Phone, iphone: Phone, tmp_path: Path) -> None:
    s = play.scene(5, seed=3)
    with serve(tmp_path) as server, link(iphone, server.base_url) as network:
        starter, joiner = pixel, iphone
        midway(starter, joiner, s, (server.base_url, network.base_url), found=1)

        network.cut()
        cut_at = time.monotonic()
        offline(joiner)
        play.tap_landmarks(starter, s.landmarks1[3:5], first_id=4)  # the other keeps tapping
        play.find_landmarks(joiner, s.landmarks2[1:3], first_id=2, online=False)  # so does this one
        time.sleep(max(0.0, OFFLINE_S - (time.monotonic() - cut_at)))
        on_screen = shown(joiner)
        assert not on_screen["saved"]
        assert on_screen["landmarks"] == [1, 2, 3]
        assert on_screen["find"] is None  # it cannot know of the starter's #4 yet

        network.restore()
        state = caught_up(starter, joiner, time.monotonic(), find=4)
    assert ids(state["taps"]["joiner"]) == [1, 2, 3]  # no tap lost
    assert ids(state["taps"]["starter"]) == [1, 2, 3, 4, 5]
    assert state["answer"]["in_photo"]["joiner"]["friend"] is not None


# A hidden page: its visibility said hidden (the engines here have no way to hide a page of
# their own), the page frozen (no script runs, as on a phone's locked screen) and cut off.
HIDE = """() => {
  Object.defineProperty(document, "visibilityState", { configurable: true, get: () => "hidden" });
  Object.defineProperty(document, "hidden", { configurable: true, get: () => true });
  document.dispatchEvent(new Event("visibilitychange"));
}"""
SHOW = """() => {
  delete document.visibilityState;
  delete document.hidden;
  document.dispatchEvent(new Event("visibilitychange"));
}"""


@pytest.mark.expected_console_errors(DROPPED)
def test_a_hidden_page_catches_up_when_shown(pixel: Phone, iphone: Phone, tmp_path: Path) -> None:
    assert isinstance(iphone, ChromiumPhone)
    s = play.scene(5, seed=4)
    with serve(tmp_path) as server, link(iphone, server.base_url) as network:
        starter, joiner = pixel, iphone
        midway(starter, joiner, s, (server.base_url, network.base_url), found=3)

        joiner.evaluate(HIDE)
        lifecycle = iphone.context.new_cdp_session(iphone.page)
        lifecycle.send("Page.setWebLifecycleState", {"state": "frozen"})
        network.cut()
        play.tap_landmarks(starter, s.landmarks1[3:5], first_id=4)
        network.restore()
        lifecycle.send("Page.setWebLifecycleState", {"state": "active"})
        joiner.evaluate(SHOW)
        state = caught_up(starter, joiner, time.monotonic(), find=4)
    assert ids(state["taps"]["starter"]) == [1, 2, 3, 4, 5]


@pytest.mark.engines("chromium", "webkit")
@pytest.mark.expected_console_errors(DROPPED)
def test_both_phones_catch_up_after_the_server_restarts(
    pixel: Phone, iphone: Phone, tmp_path: Path
) -> None:
    s = play.scene(5, seed=5)
    port = free_port()
    with ExitStack() as running:
        server = running.enter_context(serve(tmp_path, port=port))
        starter, joiner = pixel, iphone
        midway(starter, joiner, s, (server.base_url, server.base_url), found=2)

        running.close()  # the server stops
        offline(joiner)
        play.tap_landmarks(starter, s.landmarks1[3:4], first_id=4, online=False)
        play.find_landmarks(joiner, s.landmarks2[2:3], first_id=3, online=False)

        running.enter_context(serve(tmp_path, port=port))  # back, on its database
        state = caught_up(starter, joiner, time.monotonic(), find=4)
    assert ids(state["taps"]["joiner"]) == [1, 2, 3]
    assert ids(state["taps"]["starter"]) == [1, 2, 3, 4]
