"""`make screenshots`: the browser test's screenshots, halved, as the README's JPEGs."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from testbed.screenshots import convert


def test_each_screenshot_is_halved_into_a_jpeg_and_old_ones_go(tmp_path: Path) -> None:
    shots, docs = tmp_path / "shots", tmp_path / "docs"
    shots.mkdir()
    docs.mkdir()
    screen = np.zeros((2400, 1080, 3), np.uint8)
    screen[:, 540:] = (0, 212, 255)  # the right half the friend's yellow (BGR)
    for name in ("1-start", "2-share"):
        cv2.imwrite(str(shots / f"{name}.png"), screen)
    (docs / "3-photo-buddy.jpg").write_bytes(b"a screen that is no more")

    written = convert(shots, docs)

    assert sorted(path.name for path in docs.iterdir()) == ["1-start.jpg", "2-share.jpg"]
    assert written == [docs / "1-start.jpg", docs / "2-share.jpg"]
    half = cv2.imread(str(docs / "1-start.jpg"))
    assert half is not None
    assert half.shape == (1200, 540, 3)
    assert np.abs(half[600, 400].astype(int) - (0, 212, 255)).max() < 12


def test_nothing_to_convert_is_said(tmp_path: Path) -> None:
    with pytest.raises(SystemExit, match="run the browser test first"):
        convert(tmp_path, tmp_path / "docs")
