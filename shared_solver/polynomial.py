"""Real roots of small polynomials in closed form: the minimal solvers' last step.

``numpy.roots`` finds them as a companion matrix's eigenvalues, complex ones included, at
tens of microseconds a call; a cubic has a closed form (Cardano, or Viete's trigonometric
one for three real roots), polished here by Newton's method to full precision.
"""

from __future__ import annotations

import math

# Cubic coefficients this small against the largest are zero.
ZERO_COEFFICIENT = 1e-12


def binary_cubic_roots(k0: float, k1: float, k2: float, k3: float) -> list[tuple[float, float]]:
    """Unit (s, t), up to sign, with ``k0 s^3 + k1 s^2 t + k2 s t^2 + k3 t^3 = 0``: every
    real root of a homogeneous cubic (at most three; none when all coefficients vanish)."""
    scale = max(abs(k0), abs(k1), abs(k2), abs(k3))
    if scale == 0.0:
        return []
    if max(abs(k0), abs(k3)) <= ZERO_COEFFICIENT * scale:
        # Both ends vanish: roots at s = 0, at t = 0 and where k1 s + k2 t = 0.
        norm = math.hypot(k1, k2)
        return [(1.0, 0.0), (0.0, 1.0), (k2 / norm, -k1 / norm)]
    # Divide by the larger end coefficient: a monic cubic in s / t or in t / s.
    if abs(k0) > abs(k3):
        return [
            (x / math.hypot(1.0, x), 1.0 / math.hypot(1.0, x))
            for x in cubic_roots(k1 / k0, k2 / k0, k3 / k0)
        ]
    return [
        (1.0 / math.hypot(1.0, x), x / math.hypot(1.0, x))
        for x in cubic_roots(k2 / k3, k1 / k3, k0 / k3)
    ]


def cubic_roots(a: float, b: float, c: float) -> list[float]:
    """Real roots of ``x^3 + a x^2 + b x + c`` (Cardano or Viete), each Newton-polished."""
    shift = a / 3.0
    p = b - a * shift  # y^3 + p y + q with x = y - a / 3
    q = c + shift * (2.0 * shift * shift - b)
    half = 0.5 * q
    discriminant = half * half + p * p * p / 27.0
    if discriminant > 0.0:
        # One real root; this cube root has no cancellation and is not zero.
        cube = math.cbrt(-half - math.copysign(math.sqrt(discriminant), half))
        depressed = [cube - p / (3.0 * cube)]
    else:
        radius = math.sqrt(max(-p / 3.0, 0.0))
        if radius == 0.0:
            depressed = [0.0]
        else:
            angle = math.acos(max(-1.0, min(1.0, -half / radius**3))) / 3.0
            turn = 2.0 * math.pi / 3.0
            depressed = [2.0 * radius * math.cos(angle - k * turn) for k in range(3)]
    roots = []
    for y in depressed:
        x = y - shift
        for _ in range(2):
            slope = (3.0 * x + 2.0 * a) * x + b
            value = ((x + a) * x + b) * x + c
            if slope == 0.0:
                break
            x -= value / slope
        roots.append(x)
    return roots
