"""The README's screenshots: ``python -m testbed.screenshots SOURCE DESTINATION`` (``make
screenshots``, after the two-phone browser test has taken them in SOURCE).

Each PNG in SOURCE (full device pixels, a phone screen is about 1080 x 2400) is halved and
saved as a JPEG of the same name in DESTINATION, whose old JPEGs go first: the folder holds
exactly the screens the test shows today.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2

QUALITY = 82  # JPEG quality: text stays sharp, a screen 30-85 kB (`ls -l docs/screenshots`)


def convert(source: Path, destination: Path) -> list[Path]:
    """Halve every PNG of ``source`` into a JPEG in ``destination``; the JPEGs written."""
    shots = sorted(source.glob("*.png"))
    if not shots:
        raise SystemExit(f"no screenshots in {source}: run the browser test first")
    destination.mkdir(parents=True, exist_ok=True)
    for old in destination.glob("*.jpg"):
        old.unlink()
    written = []
    for shot in shots:
        image = cv2.imread(str(shot), cv2.IMREAD_COLOR)
        if image is None:
            raise SystemExit(f"{shot} is not a picture")
        height, width = image.shape[:2]
        half = cv2.resize(image, (width // 2, height // 2), interpolation=cv2.INTER_AREA)
        target = destination / f"{shot.stem}.jpg"
        cv2.imwrite(str(target), half, [cv2.IMWRITE_JPEG_QUALITY, QUALITY])
        written.append(target)
    return written


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source", type=Path)
    parser.add_argument("destination", type=Path)
    arguments = parser.parse_args()
    for written in convert(arguments.source, arguments.destination):
        print(written)


if __name__ == "__main__":
    main()
