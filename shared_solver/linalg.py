"""Small dense linear algebra, fast: the solver's matrices are 2x2 to 9x9.

``numpy.linalg`` spends several microseconds per call on checks and dispatch, more than the
work on a 3x3 or 7x7 matrix, and a solve makes hundreds of such calls. OpenCV's routines
(LU, Jacobi SVD) do the same work in a fraction of that, and 2x2 and 3-vector cases have
closed forms. Each function here matches its ``numpy.linalg`` namesake in what it returns
and raises (``numpy.linalg.LinAlgError`` on a singular matrix); batched (K, n, n) input stays
with numpy, where the dispatch is paid once.
"""

from __future__ import annotations

import math
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.floating[Any]]

LinAlgError = np.linalg.LinAlgError
# (a x b)_i = a_{i+1} b_{i+2} - a_{i+2} b_{i+1}, indices mod 3.
_NEXT, _AFTER = [1, 2, 0], [2, 0, 1]


def solve(a: Array, b: Array) -> Array:
    """x with ``a x = b``: a (n, n), b (n,) or (n, m); LinAlgError when a is singular."""
    vector = b.ndim == 1
    ok, x = cv2.solve(
        np.ascontiguousarray(a, dtype=np.float64),
        np.ascontiguousarray(b[:, None] if vector else b, dtype=np.float64),
        flags=cv2.DECOMP_LU,
    )
    if not ok:
        raise LinAlgError("singular matrix")
    solution = np.asarray(x, dtype=np.float64)
    return solution[:, 0] if vector else solution


def inv(a: Array) -> Array:
    """(n, n) inverse; LinAlgError when a is singular."""
    determinant, inverse = cv2.invert(
        np.ascontiguousarray(a, dtype=np.float64), flags=cv2.DECOMP_LU
    )
    if determinant == 0:
        raise LinAlgError("singular matrix")
    return np.asarray(inverse, dtype=np.float64)


def svd(a: Array) -> tuple[Array, Array, Array]:
    """(u (m, m), s (min,), vt (n, n)) with ``a = u diag(s) vt``, s descending."""
    s, u, vt = cv2.SVDecomp(np.ascontiguousarray(a, dtype=np.float64), flags=cv2.SVD_FULL_UV)
    f64 = np.float64
    return np.asarray(u, dtype=f64), np.asarray(s, dtype=f64)[:, 0], np.asarray(vt, dtype=f64)


def singular_values(a: Array) -> Array:
    """(min(m, n),) singular values, descending."""
    values = cv2.SVDecomp(np.ascontiguousarray(a, dtype=np.float64), flags=cv2.SVD_NO_UV)[0]
    return np.asarray(values, dtype=np.float64)[:, 0]


def null_vector(a: Array) -> Array:
    """(n,) unit v minimising ``|a v|``: the right singular vector of the smallest value."""
    return svd(a)[2][-1]


def norm(v: Array) -> float:
    """Euclidean norm of a vector, or Frobenius norm of a matrix."""
    flat = v.ravel()
    return math.sqrt(float(flat @ flat))


def cross(a: Array, b: Array) -> Array:
    """(3,) cross product of two 3-vectors."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def cross_rows(a: Array, b: Array) -> Array:
    """(N, 3) cross products of the rows of (N, 3) arrays (``numpy.cross`` costs several
    times more on a few rows)."""
    return a[:, _NEXT] * b[:, _AFTER] - a[:, _AFTER] * b[:, _NEXT]


def cholesky2(covariance: Array) -> Array:
    """(..., 2, 2) lower-triangular L with ``L L^T = covariance`` for symmetric
    positive-definite 2x2 matrices (..., 2, 2)."""
    a, b, c = covariance[..., 0, 0], covariance[..., 1, 0], covariance[..., 1, 1]
    l11 = np.sqrt(a)
    l21 = b / l11
    factor = np.zeros(covariance.shape)
    factor[..., 0, 0], factor[..., 1, 0], factor[..., 1, 1] = l11, l21, np.sqrt(c - l21 * l21)
    return factor


def whitener2(covariance: Array) -> Array:
    """(..., 2, 2) W with ``W^T W = covariance^-1`` (the inverse of the Cholesky factor):
    ``W (x - mean)`` has unit variance."""
    factor = cholesky2(covariance)
    l11, l21, l22 = factor[..., 0, 0], factor[..., 1, 0], factor[..., 1, 1]
    inverse = np.zeros(covariance.shape)
    inverse[..., 0, 0], inverse[..., 1, 1] = 1.0 / l11, 1.0 / l22
    inverse[..., 1, 0] = -l21 / (l11 * l22)
    return inverse
