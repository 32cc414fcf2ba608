"""The phone app over HTTPS through nginx, as `make run-cluster` serves it with the
certificate made at start-up (its errors ignored, as a person taps through the warning):
a secure context, so the screen Wake Lock the app asks for is granted. The control: the
same app over plain HTTP at a LAN address, as `make run` serves it to phones on venue
Wi-Fi, where the browser offers no Wake Lock at all.

Two replicas on one SQLite file stand in for PostgreSQL here: this is about the browser and
TLS; tests/backend/test_cluster.py runs the topology on PostgreSQL.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, Page, expect

from deploy.cluster import Cluster, cluster

VENUE = "buddy.test"  # 127.0.0.1 to the browser (conftest's VENUE_NAME), but not a loopback name
# The app's own requests for a wake lock, and what the browser answered, kept in the page.
RECORD_WAKE_LOCKS = """
window.wakeLocks = [];
if (navigator.wakeLock) {
  const request = navigator.wakeLock.request.bind(navigator.wakeLock);
  navigator.wakeLock.request = (type) => request(type).then(
    (lock) => { window.wakeLocks.push("granted " + lock.type); return lock; },
    (error) => { window.wakeLocks.push("refused " + error.name); throw error; },
  );
}
"""


@pytest.fixture
def running(tmp_path: Path) -> Iterator[Cluster]:
    with cluster(tmp_path, f"sqlite:///{tmp_path / 'buddy.db'}") as started:
        yield started


def started_session(browser: Browser, url: str) -> Page:
    """A phone that opens ``url`` and starts a search (the screen that keeps itself on)."""
    context = browser.new_context(ignore_https_errors=True)
    context.add_init_script(RECORD_WAKE_LOCKS)
    page = context.new_page()
    page.goto(url)
    page.get_by_test_id("start").click()
    expect(page.get_by_test_id("code")).to_be_visible()
    return page


def test_over_https_the_app_holds_a_wake_lock_and_over_lan_http_it_cannot(
    browser: Browser, running: Cluster
) -> None:
    https_port = running.url.rsplit(":", 1)[1]
    secure = started_session(browser, f"https://{VENUE}:{https_port}/")
    assert secure.evaluate("() => window.isSecureContext")
    secure.wait_for_function("() => window.wakeLocks.length > 0")
    assert secure.evaluate("() => window.wakeLocks") == ["granted screen"]
    secure.context.close()

    replica_port = running.replicas[0].base_url.rsplit(":", 1)[1]
    plain = started_session(browser, f"http://{VENUE}:{replica_port}/")
    assert not plain.evaluate("() => window.isSecureContext")
    assert not plain.evaluate("() => 'wakeLock' in navigator")
    assert plain.evaluate("() => window.wakeLocks") == []
    plain.context.close()
