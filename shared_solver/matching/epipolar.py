"""The answer's epipolar geometry from one photo to the other, with its uncertainty.

A landmark tapped at ``p`` in photo A lies, in photo B, on the line ``l = F p`` (Hartley &
Zisserman 9.2), whichever photo is A: from photo 2 to photo 1 the matrix is ``F^T``. The
answer's F is uncertain (``SolveResult.fundamental_covariance``) and so is the tap, so the
line is too: to first order ``C_l = J C_F J^T + F_xy C_p F_xy^T``, with ``J = d(F p)/d vec(F)``
(H & Z 5.2.3; the envelope of such lines is H & Z 11.3's hyperbola).

The landmarks both photos share also say on which side of the epipole the match lies: a
point in front of both cameras satisfies ``(e_B x q) . (F p) > 0`` for one sign of F
(Chum, Werner & Pajdla, "Joint orientation of epipoles", 2003), so only half of the line
is searched.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from .. import linalg
from ..projective import Array, homogeneous, left_epipole, right_epipole
from ..result import SolveResult

# The permutation of a 3x3 matrix's 9 entries (row by row) that transposes it.
_TRANSPOSE = np.array([3 * (k % 3) + k // 3 for k in range(9)])


@dataclass(frozen=True)
class Epipolar:
    """Epipolar geometry from photo A to photo B.

    Attributes:
        fundamental: (3, 3) F with ``q^T F p = 0`` for p in A and q in B (any scale).
        covariance: (9, 9) covariance of ``fundamental`` read row by row.
        sign: +1 or -1: the sign of F for which landmarks satisfy the oriented constraint
            ``(e_B x q) . (F p) > 0``; 0 when not known (then both halves of a line count).
    """

    fundamental: Array
    covariance: Array
    sign: int = 0

    @classmethod
    def from_result(
        cls,
        result: SolveResult,
        *,
        tapped_in: Literal[1, 2],
        landmarks1: Array | None = None,
        landmarks2: Array | None = None,
    ) -> Epipolar | None:
        """The answer's geometry from the photo a landmark was tapped in to the other.

        Args:
            result: an answer of ``solve(..., fundamental_covariance=True)``; None is
                returned when it has no uncertainty of F (not asked for, the plane model,
                four landmarks' curve, or several candidate geometries).
            tapped_in: 1 when the landmark was tapped in photo 1 (look for it in photo 2),
                2 the other way round.
            landmarks1, landmarks2: (N, 2) the landmarks both photos share (px), which
                orient the geometry; without them both halves of each line are kept.
        """
        if result.fundamental is None or result.fundamental_covariance is None:
            return None
        geometry = cls(np.array(result.fundamental), np.array(result.fundamental_covariance))
        if tapped_in == 2:
            geometry = geometry.transposed()
        if landmarks1 is None or landmarks2 is None:
            return geometry
        first, second = (landmarks1, landmarks2) if tapped_in == 1 else (landmarks2, landmarks1)
        return geometry.oriented(np.asarray(first, float), np.asarray(second, float))

    def transposed(self) -> Epipolar:
        """The same geometry from photo B to photo A."""
        covariance = self.covariance[np.ix_(_TRANSPOSE, _TRANSPOSE)]
        return Epipolar(self.fundamental.T.copy(), covariance, self.sign)

    def oriented(self, points_a: Array, points_b: Array) -> Epipolar:
        """The geometry with ``sign`` taken from corresponding landmarks (N, 2) in A and B:
        the sign most of them agree on (a mis-tapped one does not change it)."""
        votes = np.sign(_oriented_products(self.fundamental, points_a, points_b))
        total = float(votes.sum())
        return Epipolar(self.fundamental, self.covariance, 0 if total == 0 else int(np.sign(total)))

    @property
    def epipole_a(self) -> Array:
        """(3,) homogeneous epipole in A, ``F e_A = 0``, w >= 0."""
        return _w_positive(right_epipole(self.fundamental))

    @property
    def epipole_b(self) -> Array:
        """(3,) homogeneous epipole in B, ``F^T e_B = 0``, w >= 0."""
        return _w_positive(left_epipole(self.fundamental))

    def line(self, point: Array, point_covariance: Array) -> tuple[Array, Array] | None:
        """The line in B of a point (2,) in A with covariance (2, 2) px^2.

        Returns:
            (l (3,) scaled so that ``l[0]^2 + l[1]^2 = 1``, so ``l . (x, y, 1)`` is a
            signed distance in px; its (3, 3) covariance, first order); None for the
            epipole in A (a landmark tapped on the other friend), whose line is every line.
        """
        p = np.array([point[0], point[1], 1.0])
        line = self.fundamental @ p
        normal = float(np.hypot(line[0], line[1]))
        if not (normal > 0.0 and math.isfinite(normal)):
            return None
        jacobian = np.kron(np.eye(3), p[None, :])  # d(F p) / d vec(F), row by row
        covariance = jacobian @ self.covariance @ jacobian.T
        covariance += self.fundamental[:, :2] @ point_covariance @ self.fundamental[:, :2].T
        scale = 1.0 / normal
        return line * scale, covariance * scale**2

    def direction(self, points_a: Array) -> Array:
        """(N, 2) unit direction, in B, of the half-line from ``e_B`` on which each A point's
        match lies (with ``sign`` 0: one of the two, consistently for nearby points)."""
        lines = homogeneous(points_a) @ self.fundamental.T
        directions = np.column_stack([lines[:, 1], -lines[:, 0]])
        directions /= np.hypot(directions[:, 0], directions[:, 1])[:, None]
        if self.sign == 0:
            return directions
        e_b = self.epipole_b
        steps = np.column_stack([directions, np.zeros(len(directions))])
        # (e_B x (d, 0)) . l: the oriented constraint for points e_B + t d, t > 0.
        along = np.einsum(
            "ni,ni->n", linalg.cross_rows(np.broadcast_to(e_b, steps.shape), steps), lines
        )
        return directions * np.where(along * self.sign >= 0, 1.0, -1.0)[:, None]


def _oriented_products(fundamental: Array, points_a: Array, points_b: Array) -> Array:
    """(N,) ``(e_B x q) . (F p)`` of each landmark, with e_B at w >= 0."""
    e_b = _w_positive(left_epipole(fundamental))
    q = homogeneous(points_b)
    crossed = linalg.cross_rows(np.broadcast_to(e_b, q.shape), q)
    return np.einsum("ni,ni->n", crossed, homogeneous(points_a) @ fundamental.T)


def _w_positive(point: Array) -> Array:
    return -point if point[2] < 0 else point
