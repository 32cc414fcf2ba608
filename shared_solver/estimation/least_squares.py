"""Levenberg-Marquardt for small models, and first-order covariance with a scale gauge.

Projective models are homogeneous (a matrix up to scale), so one direction of the
parameters changes nothing: the gauge. Steps are damped so that direction costs nothing to
leave alone, and covariances are taken in the complement of it. Models on a manifold (a
rotation, a unit vector) take their steps in the tangent space and map them back with a
``retract`` of their own.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

import numpy as np

from .. import linalg
from ..linalg import Array

Residuals = Callable[[Array], tuple[Array, Array]]
State = TypeVar("State")


def levenberg_marquardt(
    residuals: Callable[[State], tuple[Array, Array]],
    start: State,
    *,
    renormalise: Callable[[State], State] = lambda theta: theta,
    retract: Callable[[State, Array], State] | None = None,
    max_iterations: int = 50,
    gain_tolerance: tuple[float, float] = (1e-10, 0.0),
) -> tuple[State, Array, Array]:
    """Minimise ``|r(theta)|^2``.

    Args:
        residuals: theta -> (r (M,), J (M, P)), J the Jacobian of r w.r.t. a step.
        start: initial parameters, of order one (normalised coordinates): a vector (P,),
            or with ``retract`` any state, e.g. a rotation and unit vectors.
        renormalise: puts theta back on its gauge (e.g. unit norm) after each step.
        retract: (theta, step (P,)) -> the state moved by a step, for parameters on a
            manifold whose steps live in the tangent space; by default
            ``renormalise(theta + step)`` on a vector.
        max_iterations: a bound; well-started problems converge in a handful.
        gain_tolerance: (relative, absolute): stop once a step lowers the cost by no more
            than ``relative * cost + absolute``.

    Returns:
        (theta, r, J) at the minimum found.
    """
    move: Callable[[State, Array], State] = retract or (
        lambda theta, step: renormalise(theta + step)  # type: ignore[operator]
    )
    theta = renormalise(start)
    r, jacobian = residuals(theta)
    cost = float(r @ r)
    damping = 1e-6  # start close to Gauss-Newton: starts come from a linear solution
    growth = 2.0
    normal, gradient, scaling = _normal_equations(r, jacobian)
    for _ in range(max_iterations):
        # A rejected step leaves the point, and so the normal equations, as they were.
        damped = normal.copy()  # + diag(damping * scaling), without np.diag's new matrix
        damped.flat[:: len(scaling) + 1] += damping * scaling
        try:
            step = linalg.solve(damped, -gradient)
        except linalg.LinAlgError:
            damping *= growth
            growth *= 2.0
            continue
        # The reduction the linear model predicts; when even that is below the tolerance,
        # the minimum is reached without trying the step.
        predicted = float(damping * step @ (scaling * step) - step @ gradient)
        if predicted <= gain_tolerance[0] * cost + gain_tolerance[1]:
            break
        trial = move(theta, step)
        r_trial, jacobian_trial = residuals(trial)
        cost_trial = float(r_trial @ r_trial)
        # The gain ratio: the reduction achieved over the predicted one (Nielsen's damping
        # update: no zig-zag between too much and too little damping).
        ratio = (cost - cost_trial) / predicted if predicted > 0 else -1.0
        if cost_trial <= cost:
            theta, r, jacobian = trial, r_trial, jacobian_trial
            normal, gradient, scaling = _normal_equations(r, jacobian)
            size = float(theta @ theta) if isinstance(theta, np.ndarray) else 1.0
            small_step = float(step @ step) <= 1e-20 * size
            small_gain = cost - cost_trial <= gain_tolerance[0] * cost + gain_tolerance[1]
            cost = cost_trial
            damping = max(damping * max(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3), 1e-12)
            growth = 2.0
            if small_step or small_gain or cost == 0.0:
                break
        else:
            damping *= growth
            growth *= 2.0
            if damping > 1e8:
                break
    return theta, r, jacobian


def _normal_equations(r: Array, jacobian: Array) -> tuple[Array, Array, Array]:
    """``J^T J``, ``J^T r`` and the damping's scale, ``diag(J^T J)`` (Marquardt's)."""
    normal = jacobian.T @ jacobian
    return normal, jacobian.T @ r, np.maximum(normal.diagonal(), 1e-12)


def gauge_free_covariance(jacobian: Array, gauge: Array, sigma: float) -> Array:
    """First-order covariance ``sigma^2 (J^T J)^+`` with the gauge direction removed.

    Args:
        jacobian: (M, P) Jacobian of residuals whitened to unit variance per ``sigma``.
        gauge: (P,) the direction along which the model does not change.
        sigma: standard deviation of one residual in the residuals' units.

    Returns:
        (P, P) covariance, zero along ``gauge``.
    """
    g = gauge / linalg.norm(gauge)
    # Orthonormal basis of the complement of g: a Householder reflection's last P-1 columns.
    v = g.copy()
    v[0] += np.copysign(1.0, g[0])
    reflection = np.eye(len(g)) - 2.0 * np.outer(v, v) / (v @ v)
    complement = reflection[:, 1:]
    reduced = jacobian @ complement
    # From the SVD of the reduced Jacobian, not by inverting J^T J: near a degenerate layout
    # (a plane fit with few landmarks to spare) J^T J's condition number reached 1e16, and
    # its LU inverse came out neither symmetric nor positive, a different "covariance" at
    # each scale of the same photos. V diag(1 / s^2) V^T is symmetric and positive by
    # construction, and as precise as the Jacobian itself.
    _, singular, vt = np.linalg.svd(reduced, full_matrices=False)
    with np.errstate(divide="ignore"):
        inverse = (vt.T / singular**2) @ vt
    return sigma**2 * complement @ inverse @ complement.T
