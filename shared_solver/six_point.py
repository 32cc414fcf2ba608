"""Six landmarks and a line through the buddy: both epipoles (paper 3.3).

With ``e1 = s a + t b`` on the given line, the 9x9 system of six landmark equations
``q^T F p = 0`` and the three equations ``F e1 = 0`` is singular exactly when its
determinant, a homogeneous cubic in ``(s, t)``, vanishes. Every real root gives a candidate
geometry; the true one is among them, and the others are ranked below it by physical
plausibility (:mod:`shared_solver.plausibility`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from . import validation
from .errors import ErrorCode, SolverError
from .five_point import canonical, left_epipole
from .plausibility import Plausibility, assess
from .projective import Array, hartley_normaliser, homogeneous, transform

# Sample angles for the cubic: (cos, sin) pairs spread over half a turn.
_ANGLES = np.pi * np.arange(4) / 4


@dataclass(frozen=True)
class EpipoleCandidate:
    """One real solution: homogeneous epipoles, its F, and its rank (1 = most plausible).

    Fields are readable as attributes or by name (``candidate["epipole2"]``), like the JSON.
    """

    epipole1: Array
    epipole2: Array
    fundamental: Array
    rank: int
    plausibility: Plausibility

    def __getitem__(self, name: str) -> Any:
        return getattr(self, name)


def epipoles_from_six(
    line1: ArrayLike,
    pts1: ArrayLike,
    pts2: ArrayLike,
    *,
    image_size1: tuple[float, float] | None = None,
    image_size2: tuple[float, float] | None = None,
) -> list[EpipoleCandidate]:
    """Every geometry with the buddy on ``line1`` that fits 6 landmarks (paper 3.3), ranked.

    Args:
        line1: (3,) line ``(a, b, c)``, ``a x + b y + c = 0`` in photo-1 pixels, through the
            buddy (epipole 1).
        pts1: (6, 2) landmarks in photo 1, pixels.
        pts2: (6, 2) the same landmarks in photo 2, pixels.
        image_size1, image_size2: (width, height) of the photos, for the plausibility of the
            implied focal lengths and whether epipoles fall inside; optional.

    Returns:
        Candidates ordered by ``rank`` (1 first): the oriented epipolar constraint, then
        phone-like implied focal lengths, then epipoles inside the photos. Each has
        ``epipole1``, ``epipole2`` (3,) homogeneous unit vectors, ``fundamental`` (3, 3).

    Raises:
        SolverError: invalid or degenerate input, or no real solution.
    """
    line = validation.line(line1, "line1")
    p, q = validation.landmark_pairs(pts1, pts2, minimum=6, maximum=6)
    t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
    p_n, q_n = transform(t1, homogeneous(p)), transform(t2, homogeneous(q))
    line_n = np.linalg.solve(t1.T, line)  # lines map by the inverse transpose
    # a: the line's point nearest the (normalised) origin; b: its point at infinity.
    a = np.array([-line_n[0] * line_n[2], -line_n[1] * line_n[2], line_n[0] ** 2 + line_n[1] ** 2])
    b = np.array([line_n[1], -line_n[0], 0.0])
    a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
    landmark_rows = np.einsum("ni,nj->nij", q_n, p_n).reshape(6, 9)

    def system(e1: Array) -> Array:
        epipole_rows = np.kron(np.eye(3), e1)  # row r: (F e1)_r as a function of vec(F)
        return np.vstack([landmark_rows, epipole_rows])

    roots = _real_roots([np.linalg.det(system(np.cos(t) * a + np.sin(t) * b)) for t in _ANGLES])
    candidates = []
    for s, t in roots:
        e1_n = s * a + t * b
        _, singular, vt = np.linalg.svd(system(e1_n))
        if singular[-2] <= 1e-9 * singular[0]:
            continue  # more than one F: this root does not fix the geometry
        fundamental = t2.T @ vt[-1].reshape(3, 3) @ t1
        if np.linalg.matrix_rank(fundamental / np.linalg.norm(fundamental), tol=1e-9) < 2:
            continue
        e1 = canonical(np.linalg.solve(t1, e1_n))
        e2 = canonical(left_epipole(fundamental))
        fundamental = canonical_matrix(fundamental)
        candidates.append(
            (
                e1,
                e2,
                fundamental,
                assess(fundamental, e1, e2, p, q, image_size1=image_size1, image_size2=image_size2),
            )
        )
    if not candidates:
        raise SolverError(
            ErrorCode.NO_SOLUTION,
            "No position along the line fits these 6 landmarks; "
            "re-check the landmarks and the line.",
        )
    candidates.sort(key=lambda c: c[3].sort_key())
    return [
        EpipoleCandidate(e1, e2, f, rank, cue)
        for rank, (e1, e2, f, cue) in enumerate(candidates, 1)
    ]


def canonical_matrix(matrix: Array) -> Array:
    """Unit Frobenius norm with the largest-magnitude entry positive."""
    matrix = matrix / np.linalg.norm(matrix)
    return matrix if matrix.flat[np.argmax(np.abs(matrix))] > 0 else -matrix


def _real_roots(samples: list[float]) -> list[tuple[float, float]]:
    """Real roots (s, t), unit norm, of the homogeneous cubic sampled at ``_ANGLES``."""
    c, s = np.cos(_ANGLES), np.sin(_ANGLES)
    # det(s a + t b) = k0 s^3 + k1 s^2 t + k2 s t^2 + k3 t^3
    basis = np.column_stack([c**3, c**2 * s, c * s**2, s**3])
    k0, k1, k2, k3 = np.linalg.solve(basis, samples)
    scale = max(abs(k0), abs(k1), abs(k2), abs(k3))
    if scale == 0:
        raise SolverError(
            ErrorCode.DEGENERATE_CONFIGURATION,
            "Every point of the line fits these landmarks; add landmarks in other directions.",
        )
    roots: list[tuple[float, float]] = []
    # In tau = t / s; a vanishing leading coefficient is a root at s = 0.
    for tau in np.roots([k3, k2, k1, k0] if abs(k3) > 1e-12 * scale else [k2, k1, k0]):
        if abs(tau.imag) <= 1e-7 * (1 + abs(tau)):
            norm = np.hypot(1.0, tau.real)
            roots.append((1.0 / norm, tau.real / norm))
    if abs(k3) <= 1e-12 * scale:
        roots.append((0.0, 1.0))
    return roots
