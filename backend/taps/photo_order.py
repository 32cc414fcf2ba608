"""Which phone's photo is the solver's photo 1, and which its photo 2.

The solver numbers the photos (``epipole1`` is friend 2 marked in photo 1, the answer is
friend 1 in photo 2); the friends have roles. Photo 1 is the photo of the friend who marked
the other (``problem.problem`` chooses it: a point before a line, the starter before the
joiner), photo 2 the other phone's, where the answer finds the friend. Everything in
``backend.taps`` that turns one into the other goes through :class:`PhotoOrder`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from backend.participants import Role, other

PhotoNumber = Literal[1, 2]


@dataclass(frozen=True)
class PhotoOrder:
    """The solver's photos by role: ``first``'s photo is photo 1, ``second``'s photo 2."""

    first: Role

    @property
    def second(self) -> Role:
        return other(self.first)

    def number(self, role: Role) -> PhotoNumber:
        """Which of the solver's photos is ``role``'s."""
        return 1 if role == self.first else 2

    def role(self, number: PhotoNumber) -> Role:
        """Whose photo is the solver's photo ``number``."""
        return self.first if number == 1 else self.second
