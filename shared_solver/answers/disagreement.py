"""When the taps do not fit two phone cameras: the projective answer, or a region over both.

The camera model's chi-square test fails for one honest search in a thousand
(``pinhole.LEVEL``), and for photos that are not what a phone writes (stretched, edited).
Falling back to the paper's projective answer is right when that answer is about as sure:
it holds whatever the cameras are. But with few landmarks the projective answer is much
less certain (five landmarks and the friend: a 90th percentile eight times the camera
model's on phone scenes), and jumping to it on a false alarm moved the friend across the
hall. So when the projective region is much larger, the answer keeps the camera model's
position and claims a region that holds both readings (the truth is in one of them), graded
by that region and saying why; when the projective answer is a curve (four landmarks), the
curve is the answer.
"""

from __future__ import annotations

import math

import numpy as np

from .. import linalg
from ..errors import WarningCode
from ..estimation.uncertainty import covering, ellipse, holdable, quality
from ..projective import Array
from ..result import Ellipse, Quality, SolveResult, SolverWarning, Uncertainty
from .building import covariance9
from .request import Request

# The projective answer is "much less certain" when its region is this many times the
# camera model's in area (twice as wide each way).
_MUCH_LESS_CERTAIN = 4.0


def reconcile(request: Request, camera: SolveResult | None, projective: SolveResult) -> SolveResult:
    """The answer when the camera model's fit failed its test (or found no pose).

    Args:
        request: the parsed taps and photos.
        camera: the camera model's answer despite the failed test; None when no pose fit.
        projective: the paper's answer on the same taps.
    """
    fallback = projective.model_copy(
        update={
            "warnings": [
                SolverWarning.of(WarningCode.CAMERA_MODEL_DISAGREES),
                *projective.warnings,
            ]
        }
    )
    if camera is None or projective.epipole2 is None:
        return fallback  # no camera answer, or the projective one is the curve: say so
    own, other = _region(camera), _region(projective)
    if own is None or other is None:
        return fallback
    if _area(other[1]) <= _MUCH_LESS_CERTAIN * _area(own[1]):
        return fallback
    centre, covariance = own[0], covering(own, other)
    centre_xy, axes, angle = ellipse(centre, covariance)
    if not holdable(axes):
        return fallback
    grade = quality(axes[0], request.diagonal2)
    warnings = [SolverWarning.of(WarningCode.CAMERA_MODEL_UNSURE), *camera.warnings]
    if grade == "poor" and WarningCode.UNCERTAIN not in {w.code for w in warnings}:
        warnings.append(SolverWarning.of(WarningCode.UNCERTAIN))
    spread = _growth(own[1], covariance)
    return camera.model_copy(
        update={
            "uncertainty": Uncertainty(
                ellipse=Ellipse(center=centre_xy, axes=axes, angle_deg=angle),
                covariance=(
                    (float(covariance[0, 0]), float(covariance[0, 1])),
                    (float(covariance[1, 0]), float(covariance[1, 1])),
                ),
            ),
            "quality": _weaker(camera.quality, grade),
            "warnings": warnings,
            "fundamental_covariance": None
            if camera.fundamental_covariance is None
            else covariance9(np.asarray(camera.fundamental_covariance) * spread),
        }
    )


def _region(answer: SolveResult) -> tuple[Array, Array] | None:
    """(centre (2,), covariance (2, 2)) of an answer's 95 % region, None without one."""
    uncertainty = answer.uncertainty
    if answer.epipole2 is None or uncertainty is None or uncertainty.covariance is None:
        return None
    covariance = np.asarray(uncertainty.covariance, dtype=np.float64)
    if not np.all(np.isfinite(covariance)):
        return None
    return np.asarray(answer.epipole2, dtype=np.float64), covariance


def _area(covariance: Array) -> float:
    return math.sqrt(max(float(np.linalg.det(covariance)), 0.0))


def _growth(narrow: Array, wide: Array) -> float:
    """How many times wider (in variance, the largest direction) ``wide`` is than
    ``narrow``: the factor for F's covariance, so a landmark's band widens with the region."""
    return max(1.0, float(np.linalg.eigvals(linalg.solve(narrow, wide)).real.max()))


_GRADES: tuple[Quality, ...] = ("good", "fair", "poor")


def _weaker(first: Quality, second: Quality) -> Quality:
    return _GRADES[max(_GRADES.index(first), _GRADES.index(second))]
