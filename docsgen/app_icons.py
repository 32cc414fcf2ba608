"""The phone app's icons (its web app manifest's, and the home screen's), drawn as one SVG in
the one palette (``shared_solver/drawing/palette.json``) and rasterised by Chromium.

Regenerate after a change to the mark or the palette, and commit what it writes::

    PYTHONPATH=. python -m docsgen.app_icons

It writes ``frontend/public/``: ``icon.svg`` (the mark), ``icon-192.png`` and
``icon-512.png`` (the mark on its rounded tile, transparent corners) and
``icon-maskable-512.png`` (the tile's colour to every edge, the mark inside the middle 80 %
circle that every launcher's mask keeps). Chromium draws the SVG exactly as a browser shows
it; Pillow, which cannot read SVG, only checks what was written.
"""

from __future__ import annotations

from pathlib import Path

from PIL import Image
from playwright.sync_api import sync_playwright

from shared_solver.drawing.palette import (
    FRIEND_COLOUR_HEX,
    LANDMARK_COLOURS_HEX,
    OUTLINE_COLOUR_HEX,
)
from testbed import chromium

PUBLIC = Path(__file__).parents[1] / "frontend" / "public"
# The app's colour behind its screens and icons (also the manifest's and the page's
# theme colour: vite.config.ts reads it from the palette too).
TILE = OUTLINE_COLOUR_HEX
# The friend's star (the favicon's, in frontend/index.html) and two landmarks in the first
# two landmark colours: what the app draws on both photos.
STAR = "M16 4l3.5 7.6 8.3.9-6.2 5.6 1.8 8.2L16 22l-7.4 4.3 1.8-8.2-6.2-5.6 8.3-.9z"


def mark(*, maskable: bool) -> str:
    """The mark on a 32 x 32 view box: a rounded tile, or (``maskable``) a full square with
    the mark shrunk into the middle 80 % circle (the safe zone of maskable icons)."""
    tile = (
        f'<rect width="32" height="32" fill="{TILE}"/>'
        if maskable
        else f'<rect width="32" height="32" rx="7" fill="{TILE}"/>'
    )
    # The unshrunk mark reaches 16.7 units from the centre (the dots' far edges): 0.75 of
    # that, 12.5, fits within the safe circle's radius of 12.8.
    scale = 0.75 if maskable else 1.0
    offset = 16 * (1 - scale)
    green, blue = LANDMARK_COLOURS_HEX[0], LANDMARK_COLOURS_HEX[1]
    return (
        '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 32 32">'
        f"{tile}"
        f'<g transform="translate({offset:g} {offset:g}) scale({scale:g})">'
        f'<path d="{STAR}" fill="{FRIEND_COLOUR_HEX}"/>'
        f'<circle cx="6" cy="26.5" r="2.2" fill="{green}"/>'
        f'<circle cx="26" cy="26.5" r="2.2" fill="{blue}"/>'
        "</g></svg>"
    )


def rasterise(svg: str, size: int, path: Path) -> None:
    """``svg`` drawn by Chromium at ``size`` x ``size`` pixels into the PNG ``path``."""
    with sync_playwright() as playwright:
        browser = chromium.launch(playwright)
        page = browser.new_page(viewport={"width": size, "height": size})
        page.set_content(
            "<style>html,body{margin:0;background:transparent}svg{display:block}</style>"
            + svg.replace("<svg ", f'<svg width="{size}" height="{size}" ', 1)
        )
        page.screenshot(path=str(path), omit_background=True)
        browser.close()
    with Image.open(path) as written:
        assert written.size == (size, size), (path, written.size)


def main() -> None:
    PUBLIC.mkdir(parents=True, exist_ok=True)
    (PUBLIC / "icon.svg").write_text(mark(maskable=False) + "\n")
    for size in (192, 512):
        rasterise(mark(maskable=False), size, PUBLIC / f"icon-{size}.png")
    rasterise(mark(maskable=True), 512, PUBLIC / "icon-maskable-512.png")
    print(f"wrote {', '.join(sorted(p.name for p in PUBLIC.glob('icon*')))} in {PUBLIC.name}/")


if __name__ == "__main__":
    main()
