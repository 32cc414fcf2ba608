"""WebKit phones kept for the next test: starting one (Xvfb, WebKitWebDriver, MiniBrowser)
costs 2-4 s, most tests take two, and a test's setup was mostly that.

A phone is taken for one test and given back at its end: reset (``WebKitPhone.reset``) and
kept for the next test that asks for the same kind, or closed when it cannot be trusted
to be as new (its test failed, it was closed, its reset failed). One pool per pytest
worker (a session fixture in conftest), closed at the session's end.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from testbed.browser.webkit_phone import Screen, WebKitPhone

# What makes two phones differ: the model, its screen, and whether the virtual screen is
# square (the ``turns`` marker). The folder is not: it holds only the phone's home (its
# browser session is ephemeral anyway) and WebKitWebDriver's log, which no test reads.
Kind = tuple[str, Screen, bool]


@dataclass
class WebKitPool:
    """Free phones by kind; ``folder`` holds the homes of those it starts."""

    folder: Path
    start: Callable[[str, Screen, Path, bool], WebKitPhone] = WebKitPhone
    free: dict[Kind, list[WebKitPhone]] = field(default_factory=dict)
    started: int = 0

    def take(self, kind: Kind) -> WebKitPhone:
        """A free phone of this kind, else a new one."""
        kept = self.free.get(kind)
        if kept:
            return kept.pop()
        self.started += 1
        model, screen, turns = kind
        return self.start(model, screen, self.folder / f"phone{self.started}", turns)

    def give_back(self, kind: Kind, phone: WebKitPhone, reuse: bool) -> None:
        """Reset ``phone`` and keep it if ``reuse`` and it can be; else close it."""
        if reuse and not phone.closed:
            try:
                phone.reset()
            except Exception as failed:  # any failure: the phone is not kept
                warnings.warn(f"{phone} not kept: its reset failed: {failed!r}", stacklevel=2)
            else:
                self.free.setdefault(kind, []).append(phone)
                return
        if not phone.closed:
            phone.close()

    def close(self) -> None:
        for phones in self.free.values():
            for phone in phones:
                phone.close()
        self.free.clear()
