"""The app's JavaScript as a phone downloads it: each file of the build, gzipped.

Sizes are of the built files in ``frontend/dist`` compressed by Python's gzip at level 9
(what a server that compresses ahead of time sends; nginx at its default level 1 sends a
few per cent more), not of the bytes on the wire: the benchmark's server sends them as they
are, so that the figure does not depend on a server's setting.
"""

from __future__ import annotations

import gzip
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

DIST = Path(__file__).resolve().parents[2] / "frontend" / "dist"


@dataclass(frozen=True)
class JavaScript:
    """Gzipped bytes of some of the build's JavaScript files, and how many files."""

    files: int
    gzipped: int

    @property
    def kb(self) -> float:
        return self.gzipped / 1000


def gzipped(path: Path) -> int:
    return len(gzip.compress(path.read_bytes(), compresslevel=9, mtime=0))


def of(paths: Iterable[str], dist: Path = DIST) -> JavaScript:
    """The scripts fetched at ``paths`` (URL paths, ``/assets/...``), from the build."""
    files = sorted({dist / path.lstrip("/") for path in paths})
    return JavaScript(len(files), sum(gzipped(file) for file in files))


def every(dist: Path = DIST) -> JavaScript:
    """Every JavaScript file of the build (lazy chunks, a service worker's included)."""
    files = sorted(dist.rglob("*.js"))
    return JavaScript(len(files), sum(gzipped(file) for file in files))
