"""What a phone's screen shows, as a test reads it: a screenshot as pixels, the answer's
drawing hidden or shown (to compare the screen with and without it), and every word and
control drawn over the photo with its box."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

from .phone import Phone

# Every element drawn over the photo but the photo's own drawing, and its box (client px):
# the words and controls overlaid on the stage (the status, the whole-photo button, the
# arrow, hints, the upload bar), whatever they are; invisible ones (faded, empty) left out.
OVERLAID = """() => {
  const view = document.querySelector('[data-testid="photo-view"]');
  const stage = view.parentElement.getBoundingClientRect();
  const shown = (element) => {
    for (let e = element; e; e = e.parentElement) {
      const style = getComputedStyle(e);
      const gone = style.display === "none" || style.visibility === "hidden";
      if (gone || Number(style.opacity) < 0.05) return false;
    }
    return true;
  };
  return [...document.querySelectorAll(".tap-screen *")]
    .filter((e) => !view.contains(e) && !e.contains(view) && !e.closest(".visually-hidden"))
    .filter((e) => !e.classList.contains("photo-controls"))
    .filter((e) => e.getClientRects().length > 0 && shown(e))
    .map((e) => [e.tagName.toLowerCase() + "." + String(e.className), e.getBoundingClientRect()])
    .filter(([, r]) => r.width > 0 && r.height > 0 && r.left < stage.right && r.right > stage.left
                       && r.top < stage.bottom && r.bottom > stage.top)
    .map(([name, r]) => [name, r.left, r.top, r.right, r.bottom]);
}"""


def screen_pixels(page: Phone, folder: Path, name: str) -> tuple[np.ndarray, float]:
    """The visible page as an (H, W, 3) array, and its device px per CSS px."""
    path = folder / f"{name}.png"
    page.screenshot(path=path)
    with Image.open(path) as shot:
        pixels = np.array(shot.convert("RGB")).astype(int)
    ratio = pixels.shape[1] / float(page.evaluate("() => innerWidth"))
    return pixels, ratio


def set_answer_shown(page: Phone, shown: bool) -> None:
    # Through the CSSOM, which the page's Content-Security-Policy allows.
    page.evaluate(
        """(shown) => {
            for (const layer of document.querySelectorAll('[data-testid="answer-layer"]'))
                layer.style.visibility = shown ? "" : "hidden"; }""",
        shown,
    )
