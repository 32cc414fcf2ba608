"""Points of the pinhole model's parameter space: K relative poses with focal lengths.

Seven parameters (the package docstring): the rotation (3), friend 2's direction (2) and the
two log focal lengths (2). A step is taken in the tangent space: ``exp([w]x) R`` for the
rotation, a step in the plane orthogonal to friend 2's unit direction, and plain steps of
the log focal lengths.

Friend 2's direction is kept as a camera of a fixed reference focal length would see it,
``u``, and ``b1 ~ diag(r, r, 1) u`` with ``r = f_reference / f1``: friend 2's pixel then
does not move when the focal length does, and a step in ``f1`` does not fight friend 2's
tap.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import cv2
import numpy as np

from ... import linalg
from ...projective import Array

# Parameters: rotation step (3), friend 2's direction step in its tangent plane (2), log focal
# steps (2).
PARAMETERS = 7
ROTATION, FRIEND2, FOCAL1, FOCAL2 = slice(0, 3), slice(3, 5), 5, 6
# Logarithms beyond this overflow (or underflow to zero) in math.exp: a fit that runs off to
# such focal lengths gets non-finite residuals, and its step is rejected.
LOG_RANGE = 700.0


@dataclass(frozen=True)
class Poses:
    """K relative poses with focal lengths: points of the model's parameter space.

    Attributes:
        rotation: (K, 3, 3) R from frame 1 to frame 2.
        friend2: (K, 3) unit u: friend 2's direction as seen with photo 1's reference focal
            length (module docstring).
        log_focals: (K, 2) ln(f1), ln(f2), f in px.
        reference: ln of photo 1's reference focal length, px.
    """

    rotation: Array
    friend2: Array
    log_focals: Array
    reference: float

    @classmethod
    def one(cls, rotation: Array, baseline: Array, log_focals: Array) -> Poses:
        """A batch of one: R (3, 3), b1 (3,) (any length), (ln f1, ln f2); the reference is
        this f1, so friend 2's direction is b1 itself."""
        baseline = np.asarray(baseline, dtype=np.float64)
        log_focals = np.asarray(log_focals, dtype=np.float64)
        return cls(
            np.asarray(rotation, dtype=np.float64)[None],
            (baseline / linalg.norm(baseline))[None],
            log_focals[None],
            float(log_focals[0]),
        )

    def __len__(self) -> int:
        return len(self.rotation)

    def moved(self, steps: Array) -> Poses:
        """A batch of one after a tangent step (1, 7): ``exp([w]x) R``, friend 2, log focals;
        in plain floats and OpenCV (this runs at every step of every fit)."""
        step = steps[0]
        x, y, z = self.friend2[0].tolist()
        (fx, sx), (fy, sy), (fz, sz) = tangent_basis(x, y, z)
        a, b = step[3:5].tolist()
        x, y, z = x + fx * a + sx * b, y + fy * a + sy * b, z + fz * a + sz * b
        norm = math.sqrt(x * x + y * y + z * z)
        turn, _ = cv2.Rodrigues(step[:3])
        return Poses(
            (turn @ self.rotation[0])[None],
            np.array([[x / norm, y / norm, z / norm]]),
            self.log_focals + step[5:7],
            self.reference,
        )

    def after_steps(self, steps: Array) -> Poses:
        """K poses: this one (a batch of one) after each of K tangent steps (K, 7), as
        :meth:`moved` does one (Rodrigues' formula on the rotations, in a batch)."""
        tangent = np.array(tangent_basis(*self.friend2[0].tolist()))
        friend2 = self.friend2[0] + steps[:, FRIEND2] @ tangent.T
        friend2 /= np.sqrt(np.einsum("ki,ki->k", friend2, friend2))[:, None]
        w = steps[:, ROTATION]
        squared = np.einsum("ki,ki->k", w, w)
        angle = np.sqrt(squared)
        small = angle < 1e-8
        safe = np.where(small, 1.0, angle)
        first = np.sin(safe) / safe
        second = (1.0 - np.cos(safe)) / (safe * safe)
        if small.any():  # no turn at all: the formula's limits (rare: skip two np.where)
            first[small], second[small] = 1.0, 0.5
        # I + a [w]x + b [w]x^2, with [w]x^2 = w w^T - |w|^2 I: no product of the (K, 3, 3).
        turn = second[:, None, None] * (w[:, :, None] * w[:, None, :])
        turn += skews(first[:, None] * w)
        turn.reshape(-1, 9)[:, ::4] += (1.0 - second * squared)[:, None]
        return Poses(
            turn @ self.rotation[0],
            friend2,
            self.log_focals[0] + steps[:, 5:7],
            self.reference,
        )

    @functools.cached_property
    def ratio(self) -> Array:
        """(K,) f_reference / f1."""
        return np.exp(self.reference - self.log_focals[:, 0])

    @functools.cached_property
    def baseline(self) -> Array:
        """(K, 3) b1 up to a positive scale: from camera 1 towards camera 2, frame 1."""
        baseline = self.friend2.copy()
        baseline[:, :2] *= self.ratio[:, None]
        return baseline

    def member(self, k: int) -> Poses:
        """The k-th pose as a batch of one."""
        return Poses(
            self.rotation[k : k + 1],
            self.friend2[k : k + 1],
            self.log_focals[k : k + 1],
            self.reference,
        )


def tangent_basis(x: float, y: float, z: float) -> list[list[float]]:
    """(3, 2) as rows: an orthonormal basis of the plane orthogonal to a unit vector, in
    plain floats (numpy's cross product costs more than all of this)."""
    fx, fy, fz = (-z, 0.0, x) if abs(x) >= 0.9 else (0.0, z, -y)
    norm = math.sqrt(fx * fx + fy * fy + fz * fz)
    fx, fy, fz = fx / norm, fy / norm, fz / norm
    return [[fx, y * fz - z * fy], [fy, z * fx - x * fz], [fz, x * fy - y * fx]]


def skews(v: Array) -> Array:
    """(K, 3, 3) cross-product matrices of (K, 3) vectors: ``sum_i v_i [e_i]x`` as one
    product (each entry is one ``+-v_i``, exactly; a third of the time of filling them in)."""
    return (v @ _GENERATORS).reshape(-1, 3, 3)


# [e_x]x, [e_y]x, [e_z]x, each flattened: rows of the product in skews.
_GENERATORS = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    ]
)
