"""Levenberg-Marquardt for small models, and first-order covariance with a scale gauge.

Models here are homogeneous (a matrix up to scale), so one direction of the parameters
changes nothing: the gauge. Steps are damped so that direction costs nothing to leave
alone, and covariances are taken in the complement of it.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..projective import Array

Residuals = Callable[[Array], tuple[Array, Array]]


def levenberg_marquardt(
    residuals: Residuals,
    start: Array,
    *,
    renormalise: Callable[[Array], Array] = lambda theta: theta,
    max_iterations: int = 50,
) -> tuple[Array, Array, Array]:
    """Minimise ``|r(theta)|^2``.

    Args:
        residuals: theta (P,) -> (r (M,), J (M, P)), J the Jacobian of r.
        start: (P,) initial parameters, of order one (normalised coordinates).
        renormalise: puts theta back on its gauge (e.g. unit norm) after each step.
        max_iterations: a bound; well-started problems converge in a handful.

    Returns:
        (theta, r, J) at the minimum found.
    """
    theta = renormalise(start)
    r, jacobian = residuals(theta)
    cost = float(r @ r)
    damping = 1e-6  # start close to Gauss-Newton: starts come from a linear solution
    for _ in range(max_iterations):
        normal = jacobian.T @ jacobian
        gradient = jacobian.T @ r
        damped = normal + damping * np.diag(np.maximum(np.diag(normal), 1e-12))
        try:
            step = np.linalg.solve(damped, -gradient)
        except np.linalg.LinAlgError:
            damping *= 10
            continue
        trial = renormalise(theta + step)
        r_trial, jacobian_trial = residuals(trial)
        cost_trial = float(r_trial @ r_trial)
        if cost_trial <= cost:
            theta, r, jacobian = trial, r_trial, jacobian_trial
            small_step = float(step @ step) <= 1e-20 * float(theta @ theta)
            small_gain = cost - cost_trial <= 1e-10 * cost
            cost = cost_trial
            damping = max(damping / 10, 1e-12)
            if small_step or small_gain or cost == 0.0:
                break
        else:
            damping *= 10
            if damping > 1e8:
                break
    return theta, r, jacobian


def gauge_free_covariance(jacobian: Array, gauge: Array, sigma: float) -> Array:
    """First-order covariance ``sigma^2 (J^T J)^+`` with the gauge direction removed.

    Args:
        jacobian: (M, P) Jacobian of residuals whitened to unit variance per ``sigma``.
        gauge: (P,) the direction along which the model does not change.
        sigma: standard deviation of one residual in the residuals' units.

    Returns:
        (P, P) covariance, zero along ``gauge``.
    """
    g = gauge / np.linalg.norm(gauge)
    # Orthonormal basis of the complement of g: a Householder reflection's last P-1 columns.
    v = g.copy()
    v[0] += np.copysign(1.0, g[0])
    reflection = np.eye(len(g)) - 2.0 * np.outer(v, v) / (v @ v)
    complement = reflection[:, 1:]
    reduced = jacobian @ complement
    information = reduced.T @ reduced
    try:
        inverse = np.linalg.inv(information)
    except np.linalg.LinAlgError:
        inverse = np.linalg.pinv(information, hermitian=True)
    return sigma**2 * complement @ inverse @ complement.T
