"""Five landmarks and friend 2's position, the linear route (paper 3.2; Ito et al.).

``F e1 = 0`` and ``q^T F p = 0``: writing ``F = A B^T`` with ``B`` spanning the plane
orthogonal to ``e1`` leaves 6 unknowns (the columns of ``A``) and one linear equation per
landmark; ``e2 = a1 x a2``. This is the 8x9 null-space system of Ito et al. with the epipole
constraint eliminated: exact for five landmarks, least squares for more (the start of the
maximum-likelihood fit).
"""

from __future__ import annotations

import numpy as np

from .. import linalg
from ..errors import Reason
from ..projective import (
    Array,
    hartley_normaliser,
    homogeneous,
    orthogonal_complement,
    transform,
    unit,
)
from ..refusal import SolverError

# Below this relative singular value the system has more than one solution.
_SINGULAR = 1e-10


def fundamental_with_epipole(e1: Array, p: Array, q: Array) -> Array:
    """Least-squares F with ``F e1 = 0`` from N >= 5 landmarks, in pixel coordinates.

    Hartley-normalised; the linear route of paper 3.2 (exact for N = 5).

    Args:
        e1: (3,) homogeneous position of friend 2 in photo 1.
        p, q: (N, 2) landmarks of photo 1 and photo 2.

    Returns:
        (3, 3) F, unit Frobenius norm, ``q^T F p = 0`` and ``F e1 = 0``.
    """
    t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
    basis = orthogonal_complement(unit(t1 @ e1))
    along = transform(t1, homogeneous(p)) @ basis  # (N, 2): each landmark in that plane
    q_n = transform(t2, homogeneous(q))
    design = np.hstack([along[:, :1] * q_n, along[:, 1:] * q_n])
    _, singular, vt = linalg.svd(design)
    # Six unknowns up to scale: the geometry is fixed iff the design has rank 5.
    if singular[4] <= _SINGULAR * singular[0]:
        raise SolverError(Reason.FRIEND_UNDETERMINED)
    columns = vt[-1].reshape(2, 3).T
    fundamental = t2.T @ (columns @ basis.T) @ t1
    return fundamental / linalg.norm(fundamental)
