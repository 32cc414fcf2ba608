"""Watchers put into the phone's page before the app loads (``add_init_script``): they stamp,
on the page's own clock (``performance.now()``, which events' ``timeStamp`` share), the
moments the benchmark measures, so that neither Playwright's round trips nor Python's
clock are in the figures. The benchmark waits for them through a promise the watchers
resolve (:data:`AWAIT`): Playwright's own waiting polls on every frame, work the throttled
main thread would do beside the app's.

- ``chosen``: a photo was picked (the file input's ``change``, its event's time stamp);
- ``tappable``: then the photo view published its transform (``data-scale``) and its
  picture fired ``load``, and the frame after that is past: the photo is on screen and
  takes taps;
- per tap, ``down`` / ``lifted``: a finger touched the photo view / left it
  (``pointerdown`` / ``pointerup``, their time stamps: when the input reached the page,
  before it waited for a busy main thread); ``painted``: after that, one more landmark
  mark in the page, and the frame that draws it past (a ``requestAnimationFrame``
  callback, then the task after it: the frame's paint is done by then);
- ``events``: the browser's own Event Timing entries of the taps (the basis of Interaction
  to Next Paint): each event's wait for the main thread, its handlers' time, and its
  duration to the next paint.
"""

from __future__ import annotations

from typing import Any

from playwright.sync_api import Page

INIT = """
(() => {
  const stamps = (window.__slow = { chosen: null, tappable: null, taps: [], events: [] });
  const marks = () => document.querySelectorAll('[data-testid="landmark"]').length;
  // After the next frame: its callbacks run before its paint, the task after them follows it.
  const afterFrame = (stamp) => requestAnimationFrame(() => setTimeout(stamp, 0));
  let waiters = [];
  const settle = () => {
    waiters = waiters.filter(([done, resolve]) => (done() ? (resolve(), false) : true));
  };
  stamps.until = (what) => new Promise((resolve) => {
    const tap = stamps.taps[stamps.taps.length - 1];
    const done = what === "tappable" ? () => stamps.tappable !== null : () => tap.painted !== null;
    waiters.push([done, resolve]);
    settle();
  });
  let waitingForPhoto = false;
  let marksBefore = null;
  const check = () => {
    if (waitingForPhoto) {
      const view = document.querySelector('[data-testid="photo-view"]');
      const img = view && view.querySelector("img.layer");
      if (view && view.hasAttribute("data-scale") && img && img.complete && img.naturalWidth > 0) {
        waitingForPhoto = false;
        afterFrame(() => { stamps.tappable = performance.now(); settle(); });
      }
    }
    if (marksBefore !== null && marks() > marksBefore) {
      marksBefore = null;
      const tap = stamps.taps[stamps.taps.length - 1];
      afterFrame(() => { tap.painted = performance.now(); settle(); });
    }
  };
  const start = () => {
    new MutationObserver(check).observe(document.documentElement, {
      subtree: true, childList: true, attributes: true,
    });
  };
  if (document.documentElement) start(); else addEventListener("DOMContentLoaded", start);
  // load does not bubble; a listener capturing on the document hears every image's.
  document.addEventListener("load", check, true);
  document.addEventListener("change", (event) => {
    if (event.target instanceof HTMLInputElement && event.target.type === "file") {
      stamps.chosen = event.timeStamp;
      stamps.tappable = null;
      waitingForPhoto = true;
      check();
    }
  }, true);
  const onPhoto = (event) =>
    event.target instanceof Element && event.target.closest('[data-testid="photo-view"]');
  document.addEventListener("pointerdown", (event) => {
    if (!onPhoto(event)) return;
    stamps.taps.push({ down: event.timeStamp, lifted: null, painted: null });
    marksBefore = marks();
  }, true);
  document.addEventListener("pointerup", (event) => {
    const tap = stamps.taps[stamps.taps.length - 1];
    if (onPhoto(event) && tap) tap.lifted = event.timeStamp;
  }, true);
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) {
      stamps.events.push({
        name: e.name, start: e.startTime, processingStart: e.processingStart,
        processingEnd: e.processingEnd, duration: e.duration, interaction: e.interactionId,
      });
    }
  }).observe({ type: "event", durationThreshold: 16, buffered: true });
})();
"""

# Resolves once the photo takes taps / the last tap's mark is painted.
AWAIT = "(what) => window.__slow.until(what)"


def stamps(page: Page) -> dict[str, Any]:
    """The page's stamps (ms on its ``performance.now()`` clock, or None)."""
    result: dict[str, Any] = page.evaluate(
        "() => { const { until, ...stamps } = window.__slow; return stamps; }"
    )
    return result
