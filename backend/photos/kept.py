"""The photos a replica read lately, kept in memory for a minute: a phone asks for the crop
of each landmark the other phone taps, one after the other, and each crop read the whole
photo (300 KB to 1 MB) from the database again.

A photo is kept by its name, (session, role, the session's version that stored it): a
replaced photo has another name, so what is kept is never stale. A photo is kept at most
:data:`KEPT_SECONDS` after it was read, and never more than :data:`KEPT_BYTES` in all (the
least recently used go first): after **Delete now** a replica may hold the photo in memory
for that minute at most, never serving it (every read checks the session first). The
first read first out: a minute is about how long the landmarks of a search take.
"""

from __future__ import annotations

import threading
import time
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

from .intake import StoredPhoto
from .jpeg_rows import RowIndex, row_index

KEPT_SECONDS = 60.0
KEPT_BYTES = 64 * 2**20

Name = tuple[str, str, int]  # session, role, the session's version that stored the photo


@dataclass(frozen=True)
class KeptPhoto:
    photo: StoredPhoto
    read_at: float  # time.monotonic()

    @cached_property
    def rows(self) -> RowIndex | None:
        """Where its rows are (.jpeg_rows), found once."""
        return row_index(self.photo.data)


class KeptPhotos:
    """A bounded, thread-safe store of photos by name, in the order they were read."""

    def __init__(
        self,
        max_bytes: int = KEPT_BYTES,
        max_seconds: float = KEPT_SECONDS,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.max_bytes = max_bytes
        self.max_seconds = max_seconds
        self.clock = clock
        self._kept: OrderedDict[Name, KeptPhoto] = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()

    def get(self, name: Name, read: Callable[[], StoredPhoto | None]) -> KeptPhoto | None:
        """The photo of that name: kept, or ``read`` (None: there is none) and kept."""
        now = self.clock()
        with self._lock:
            self._forget_old(now)
            kept = self._kept.get(name)
        if kept is not None:
            return kept
        photo = read()
        if photo is None:
            return None
        kept = KeptPhoto(photo, now)
        with self._lock:
            if name not in self._kept and len(photo.data) <= self.max_bytes:
                self._kept[name] = kept
                self._bytes += len(photo.data)
                while self._bytes > self.max_bytes:
                    self._drop(next(iter(self._kept)))
        return kept

    def _forget_old(self, now: float) -> None:
        while self._kept:
            name, oldest = next(iter(self._kept.items()))
            if now - oldest.read_at <= self.max_seconds:
                return
            self._drop(name)

    def _drop(self, name: Name) -> None:
        self._bytes -= len(self._kept.pop(name).photo.data)
