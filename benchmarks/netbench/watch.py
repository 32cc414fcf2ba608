"""Watchers put into each phone's page before the app loads (``add_init_script``): they
stamp, with the page's wall clock (``Date.now()``, the same clock as the benchmark's
``time.time()`` on one machine), the moments the benchmark measures.

- ``chosen``: a photo was picked (the file input's ``change``);
- ``tappable``: then the photo view shows it (its transform published, its picture decoded);
- ``uploaded``: the photo's PUT answered (the browser's resource timing of the request);
- ``lifted``: the last finger lifted off the screen (``touchend``): a tap is placed then;
- ``text`` / ``drawn``: after :data:`WATCH_ANSWER`, the answer's position and its drawing
  on the photo (the server's image layer, ``result-overlay``, or an SVG the app draws,
  ``answer-layer``) changed from what they were.
"""

from __future__ import annotations

from typing import Any

from playwright.sync_api import Page

INIT = """
(() => {
  const stamps = (window.__bench = {
    chosen: null, tappable: null, uploaded: null, lifted: null, text: null, drawn: null,
  });
  document.addEventListener("touchend", (event) => {
    stamps.lifted = performance.timeOrigin + event.timeStamp;
  }, true);
  const tappable = () => {
    const view = document.querySelector('[data-testid="photo-view"]');
    const img = view && view.querySelector("img.layer");
    const shown = img && img.complete && img.naturalWidth > 0;
    if (view && view.hasAttribute("data-photo-width") && shown) {
      stamps.tappable = Date.now();
    } else {
      requestAnimationFrame(tappable);
    }
  };
  document.addEventListener("change", (event) => {
    if (event.target instanceof HTMLInputElement && event.target.type === "file") {
      stamps.chosen = Date.now();
      stamps.tappable = stamps.uploaded = null;
      requestAnimationFrame(tappable);
    }
  }, true);
  new PerformanceObserver((list) => {
    for (const entry of list.getEntries()) {
      const photo = new URL(entry.name).pathname.endsWith("/photo");
      if (entry.initiatorType === "xmlhttprequest" && photo) {
        stamps.uploaded = performance.timeOrigin + entry.responseEnd;
      }
    }
  }).observe({ type: "resource", buffered: true });
})();
"""

# What the answer looks like now; stamps when its position (text) and its drawing change.
WATCH_ANSWER = """
() => {
  const stamps = window.__bench;
  const position = () => {
    const p = document.querySelector('[data-testid="result-position"]');
    return p ? `${p.dataset.x},${p.dataset.y}` : null;
  };
  // The server's drawing (an image layer), or one the app draws itself (an SVG layer).
  const drawing = () => {
    const img = document.querySelector('[data-testid="result-overlay"]');
    if (img) return img.complete && img.naturalWidth > 0 ? img.currentSrc || img.src : null;
    const svg = document.querySelector('[data-testid="answer-layer"]');
    return svg && svg.childElementCount > 0 ? svg.innerHTML : null;
  };
  const before = { text: position(), drawn: drawing() };
  stamps.text = stamps.drawn = null;
  const check = () => {
    const now = Date.now();
    const [text, drawn] = [position(), drawing()];
    if (stamps.text === null && text !== null && text !== before.text) stamps.text = now;
    // The drawing of the new answer: its URL comes with the new state (after the text).
    const newer = stamps.text !== null && drawn !== null && drawn !== before.drawn;
    if (stamps.drawn === null && newer) stamps.drawn = now;
    if (stamps.text === null || stamps.drawn === null) requestAnimationFrame(check);
  };
  requestAnimationFrame(check);
}
"""


def stamps(page: Page) -> dict[str, Any]:
    """The page's stamps (ms since the epoch, or None)."""
    result: dict[str, Any] = page.evaluate("() => ({ ...window.__bench })")
    return result
