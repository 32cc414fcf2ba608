"""The photos a replica read lately, kept in memory a minute after their last use: a phone
asks for the crop of each landmark the other phone taps, one after the other, and each crop
read the whole photo (300 KB to 1 MB) from the database again.

A photo is kept by its name, (session, role, the session's version that stored it): a
replaced photo has another name, so what is kept is never stale. A photo is kept at most
:data:`KEPT_SECONDS` after it was last used, and never more than :data:`KEPT_BYTES` in all
(the least recently used go first): after **Delete now** a replica may hold the photo in
memory for that minute at most, never serving it (every read checks the session first, so a
deleted session's photo is never used again).

A search's landmarks take about 1.5 minutes, one crop every 15 s or so, and a replica serves
the crops of every search under way (the load balancer spreads the calls): kept a minute
from the first read, each photo was read again for its later crops (3.6 reads of a photo per
search in ``make bench-load``, PostgreSQL's heaviest statement); and between two crops of one
search a replica reads ~300 other photos at 400 searches at once (~95 MB at 1600 px), which
64 MB did not hold.
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
KEPT_BYTES = 160 * 2**20

Name = tuple[str, str, int]  # session, role, the session's version that stored the photo


@dataclass
class KeptPhoto:
    photo: StoredPhoto
    read_at: float  # time.monotonic() of its last use

    @cached_property
    def rows(self) -> RowIndex | None:
        """Where its rows are (.jpeg_rows), found once."""
        return row_index(self.photo.data)


class KeptPhotos:
    """A bounded, thread-safe store of photos by name, in the order they were last used."""

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
            if kept is not None:  # used again: kept a minute from now, the last to go
                kept.read_at = now
                self._kept.move_to_end(name)
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
