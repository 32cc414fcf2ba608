"""``solve``: the one entry point. It picks the method from what the two people tapped.

| given                          | landmarks | method                                         |
|--------------------------------|-----------|------------------------------------------------|
| buddy (e1) and seeker (e2)     | >= 3      | ``two_epipoles``                               |
| buddy (e1)                     | 4         | ``conic`` (a curve, not a point)               |
| buddy (e1)                     | 5         | ``five_point_epipole`` or ``planar``           |
| buddy (e1)                     | >= 6      | ``least_squares_epipole`` or ``planar``        |
| a line through the buddy       | >= 6      | ``six_point_line`` (ranked candidates)         |
| nothing                        | 7 / >= 8  | ``seven_point`` / ``eight_point`` (OpenCV)     |

Every tap is noisy (``tap_sigma`` px per axis), the buddy's included: with more than the
minimum the answer is the maximum-likelihood fit over all taps. It comes with per-landmark
residuals, suspects, a quality grade, sentences to act on, and a 95 % ellipse wherever one
was measured to hold the truth about 95 % of the time (not for the line and 7-point
fallbacks, which say so).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import validation, words
from .errors import ErrorCode, SolverError
from .estimation import bootstrap
from .estimation.epipolar_fit import (
    EpipolarFit,
    fit_epipolar,
    fit_two_epipoles,
    sampson_distances,
)
from .estimation.mistaps import consistent, find_mistaps, refit
from .estimation.planar import PlanarFit, coplanar_fit
from .estimation.plausibility import assess, orient_seeker
from .estimation.uncertainty import ellipse, quality
from .minimal.conic import conic_from_cross_ratio
from .minimal.five_point_linear import fundamental_with_epipole
from .minimal.seven_point import seven_point_roots
from .minimal.six_point_line import six_point_line_roots
from .minimal.two_epipoles import fundamental_between
from .projective import (
    Array,
    canonical,
    canonical_matrix,
    hartley_normaliser,
    homogeneous,
    skew,
    to_pixel,
    transform,
)
from .result import Candidate, Ellipse, Matrix, Method, SolveResult, Uncertainty

# Two taps closer than this many tap sigmas are the same place; landmarks within it of one
# line are collinear: degenerate at the precision of a finger.
_SAME_PLACE_SIGMAS = 0.5


@dataclass(frozen=True)
class _Taps:
    """Validated input: landmarks, what was tapped about the friends, and how precisely."""

    p: Array
    q: Array
    epipole1: Array | None
    epipole2: Array | None
    line1: Array | None
    sigma: float
    size1: tuple[float, float] | None
    size2: tuple[float, float] | None
    labels: list[int]

    @property
    def diagonal2(self) -> float:
        """Photo 2's diagonal in px (the landmarks' extent when its size is unknown)."""
        if self.size2 is not None:
            return math.hypot(*self.size2)
        return validation.spread(self.q)


def solve(
    points1: ArrayLike,
    points2: ArrayLike,
    *,
    epipole1: ArrayLike | None = None,
    epipole2: ArrayLike | None = None,
    epipolar_line1: ArrayLike | None = None,
    tap_sigma: float = 2.0,
    image_size1: ArrayLike | None = None,
    image_size2: ArrayLike | None = None,
    landmark_ids: Sequence[int] | None = None,
) -> SolveResult:
    """Where the seeker stands in the buddy's photo, from whatever the two people tapped.

    The method follows from the input (module docstring): ``conic`` is paper 3.1,
    ``five_point_epipole`` 3.2, ``six_point_line`` 3.3, ``two_epipoles`` the introduction's
    pencil homography; with more landmarks, maximum likelihood over every tap (Sampson
    distances, Hartley & Zisserman 11.4.3), and ``planar`` is ``e2 = H e1`` (docs/geometry.md).

    Args:
        points1: (N, 2) landmarks in photo 1 (the seeker's), pixels, x right, y down.
        points2: (N, 2) the same landmarks, same order, in photo 2 (the buddy's).
        epipole1: (2,) where the seeker tapped the buddy in photo 1.
        epipole2: (2,) where the buddy tapped the seeker in photo 2 (both see each other);
            needs ``epipole1``.
        epipolar_line1: (3,) line ``a x + b y + c = 0`` in photo 1 through the buddy, when
            the seeker can only say "somewhere along here"; excludes ``epipole1``.
        tap_sigma: standard deviation of a tap, px per axis: the noise the uncertainty,
            the consistency tests and the degeneracy tolerance are based on.
        image_size1, image_size2: (width, height) of the photos, px; used for plausibility,
            quality and "outside the photo" warnings.
        landmark_ids: the numbers people see on the landmarks, for messages (default 1..N).

    Returns:
        A :class:`SolveResult`; ``model_dump(mode="json")`` is the REST API's JSON.

    Raises:
        SolverError: invalid or degenerate input, with a stable ``code``.
    """
    taps = _parse(
        points1,
        points2,
        epipole1=epipole1,
        epipole2=epipole2,
        epipolar_line1=epipolar_line1,
        tap_sigma=tap_sigma,
        image_size1=image_size1,
        image_size2=image_size2,
        landmark_ids=landmark_ids,
    )
    if taps.epipole1 is not None and taps.epipole2 is not None:
        return _both_epipoles(taps)
    if taps.epipole1 is not None:
        return _conic(taps) if len(taps.p) == 4 else _buddy_tapped(taps)
    if taps.line1 is not None:
        return _line_through_buddy(taps)
    return _landmarks_only(taps)


def _parse(
    points1: ArrayLike,
    points2: ArrayLike,
    *,
    epipole1: ArrayLike | None,
    epipole2: ArrayLike | None,
    epipolar_line1: ArrayLike | None,
    tap_sigma: float,
    image_size1: ArrayLike | None,
    image_size2: ArrayLike | None,
    landmark_ids: Sequence[int] | None,
) -> _Taps:
    sigma = validation.positive(tap_sigma, "tap_sigma")
    e1 = None if epipole1 is None else validation.pixel(epipole1, "epipole1")
    e2 = None if epipole2 is None else validation.pixel(epipole2, "epipole2")
    line1 = None if epipolar_line1 is None else validation.line(epipolar_line1, "epipolar_line1")
    if e1 is not None and line1 is not None:
        raise SolverError(ErrorCode.CONFLICTING_INPUTS, words.POINT_AND_LINE)
    if e2 is not None and e1 is None:
        raise SolverError(ErrorCode.MISSING_EPIPOLE1, words.SEEKER_WITHOUT_BUDDY)
    if e1 is not None:
        minimum, purpose = (
            (3, "when both friends are marked") if e2 is not None else (4, "with the buddy marked")
        )
    elif line1 is not None:
        minimum, purpose = 6, "with a line through the buddy"
    else:
        minimum, purpose = 7, "without marking the buddy (mark the buddy to need only 5)"
    labels = None if landmark_ids is None else [int(i) for i in landmark_ids]
    p, q = validation.landmark_pairs(
        points1,
        points2,
        minimum=minimum,
        purpose=purpose,
        tolerance=_SAME_PLACE_SIGMAS * sigma,
        labels=labels,
        epipole1=None if e1 is None else np.append(e1, 1.0),
        epipole2=None if e2 is None else np.append(e2, 1.0),
    )
    if labels is not None and len(labels) != len(p):
        raise SolverError(ErrorCode.MISMATCHED_LENGTHS, words.ONE_ID_PER_LANDMARK)
    return _Taps(
        p,
        q,
        e1,
        e2,
        line1,
        sigma,
        validation.image_size(image_size1, "image_size1"),
        validation.image_size(image_size2, "image_size2"),
        labels or list(range(1, len(p) + 1)),
    )


# --- the cases -------------------------------------------------------------------------


def _conic(taps: _Taps) -> SolveResult:
    assert taps.epipole1 is not None
    t1, t2 = hartley_normaliser(taps.p), hartley_normaliser(taps.q)
    conic = conic_from_cross_ratio(
        t1 @ np.append(taps.epipole1, 1.0),
        transform(t1, homogeneous(taps.p)),
        transform(t2, homogeneous(taps.q)),
    )
    return SolveResult(
        method="conic",
        landmark_count=len(taps.p),
        tap_sigma=taps.sigma,
        epipole2=None,
        epipole2_h=None,
        epipole1=_pixel(np.append(taps.epipole1, 1.0)),
        epipole1_h=_unit(np.append(taps.epipole1, 1.0)),
        conic2=_matrix(canonical_matrix(t2.T @ conic @ t2)),
        residuals=[0.0] * len(taps.p),
        quality="fair",
        warnings=[words.ON_THE_CURVE],
    )


def _buddy_tapped(taps: _Taps) -> SolveResult:
    """The paper's case: the buddy tapped in photo 1, five or more landmarks."""
    e1 = taps.epipole1
    assert e1 is not None
    fit = fit_epipolar(
        taps.p,
        taps.q,
        fundamental_with_epipole(np.append(e1, 1.0), taps.p, taps.q),
        sigma=taps.sigma,
        epipole1_tap=e1,
    )
    suspects: list[int] = []
    warnings: list[str] = []
    if not consistent(fit, taps.sigma):
        found = (
            find_mistaps(taps.p, taps.q, taps.sigma, epipole1_tap=e1) if len(taps.p) >= 7 else None
        )
        if found is not None:
            suspects, fit = found
            warnings += _suspect_warnings(taps, suspects, fit)
    used = np.setdiff1d(np.arange(len(taps.p)), suspects)
    plane = coplanar_fit(taps.p[used], taps.q[used], sigma=taps.sigma)
    if plane is not None:
        return _result(
            "planar", taps, _Answer.of_plane(taps, plane), suspects=suspects, warnings=warnings
        )
    covariance = fit.covariance2
    if len(used) == 5:  # minimal: first order is too optimistic near degenerate layouts
        covariance = _calibrated(
            fit,
            covariance,
            lambda: bootstrap.five_point_samples(e1, taps.p[used], taps.q[used], taps.sigma),
        )
    covariance, inconsistent = _widen_if_inconsistent(fit, covariance, taps.sigma, warnings)
    method: Method = "five_point_epipole" if len(used) == 5 else "least_squares_epipole"
    return _result(
        method,
        taps,
        _Answer.of_fit(taps, fit, covariance),
        suspects=suspects,
        warnings=warnings,
        inconsistent=inconsistent,
    )


def _both_epipoles(taps: _Taps) -> SolveResult:
    assert taps.epipole1 is not None
    assert taps.epipole2 is not None
    e1h, e2h = np.append(taps.epipole1, 1.0), np.append(taps.epipole2, 1.0)
    start = fundamental_between(e1h, e2h, taps.p, taps.q)
    fit = fit_two_epipoles(
        taps.p,
        taps.q,
        start,
        sigma=taps.sigma,
        epipole1_tap=taps.epipole1,
        epipole2_tap=taps.epipole2,
    )
    warnings: list[str] = []
    covariance, inconsistent = _widen_if_inconsistent(fit, fit.covariance2, taps.sigma, warnings)
    return _result(
        "two_epipoles",
        taps,
        _Answer.of_fit(taps, fit, covariance),
        suspects=[],
        warnings=warnings,
        inconsistent=inconsistent,
    )


def _line_through_buddy(taps: _Taps) -> SolveResult:
    """Paper 3.3: the cubic's real roots on the first six landmarks, refined over all."""
    assert taps.line1 is not None
    geometries = six_point_line_roots(taps.line1, taps.p[:6], taps.q[:6])
    if not geometries:
        raise SolverError(ErrorCode.NO_SOLUTION, words.LINE_FITS_NOTHING)
    return _likeliest(taps, "six_point_line", geometries, minimal=len(taps.p) == 6)


def _landmarks_only(taps: _Taps) -> SolveResult:
    """No buddy tap: the classical 7- and 8-point methods (OpenCV), refined over all taps."""
    if coplanar_fit(taps.p, taps.q, sigma=taps.sigma) is not None:
        raise SolverError(ErrorCode.DEGENERATE_CONFIGURATION, words.ONE_SURFACE_WITHOUT_BUDDY)
    if len(taps.p) == 7:
        geometries = seven_point_roots(taps.p, taps.q)
        if not geometries:
            raise SolverError(ErrorCode.NO_SOLUTION, words.SEVEN_FIT_NOTHING)
        return _likeliest(taps, "seven_point", geometries, minimal=True)
    suspects: list[int] = []
    warnings: list[str] = []
    fit = refit(taps.p, taps.q, taps.sigma, None)
    if not consistent(fit, taps.sigma) and len(taps.p) >= 9:
        found = find_mistaps(taps.p, taps.q, taps.sigma)
        if found is not None:
            suspects, fit = found
            warnings += _suspect_warnings(taps, suspects, fit)
    covariance = fit.covariance2
    if len(taps.p) - len(suspects) == 8:  # one more than minimal: first order measured optimistic

        def refitted(rng: np.random.Generator) -> Array:
            p, q = _retapped(taps, rng)
            return _pixel_or_nan(refit(p, q, taps.sigma, None).epipole2)

        covariance = _calibrated(fit, covariance, lambda: bootstrap.resolved_samples(refitted))
    covariance, inconsistent = _widen_if_inconsistent(fit, covariance, taps.sigma, warnings)
    return _result(
        "eight_point",
        taps,
        _Answer.of_fit(taps, fit, covariance),
        suspects=suspects,
        warnings=warnings,
        inconsistent=inconsistent,
    )


def _likeliest(
    taps: _Taps, method: Method, geometries: list[tuple[Array, Array, Array]], *, minimal: bool
) -> SolveResult:
    """Several geometries fit: rank them by plausibility, answer with the first, list all.

    With more landmarks than the minimum each candidate is first refined over all of them,
    and a spurious root stops fitting. No 95 % region is claimed for these methods: measured
    on facing scenes, neither first order nor a bootstrap held the truth often enough (the
    noise can carry the answer into another root's basin), so the answer is graded 'poor'
    and says what would make it reliable.
    """
    fits = None
    if not minimal:
        fits = [
            fit_epipolar(taps.p, taps.q, f, sigma=taps.sigma, line1=taps.line1)
            for _, _, f in geometries
        ]
        geometries = [(f.epipole1, f.epipole2, f.fundamental) for f in fits]
    fit_ok = [True] * len(geometries) if fits is None else [consistent(f, taps.sigma) for f in fits]
    cues = [
        assess(f, e1, e2, taps.p, taps.q, image_size1=taps.size1, image_size2=taps.size2)
        for e1, e2, f in geometries
    ]
    order = sorted(
        range(len(geometries)),
        key=lambda i: (cues[i].hard_cues(), not fit_ok[i], cues[i].focal_deviation),
    )
    top = order[0]
    if fits is not None:
        fit = fits[top]
    else:
        fit = fit_epipolar(taps.p, taps.q, geometries[top][2], sigma=taps.sigma, line1=taps.line1)
    ambiguous = sum(cues[i].hard_cues() == cues[top].hard_cues() and fit_ok[i] for i in order) > 1
    line = taps.line1 is not None
    warnings = [words.ambiguous(line=line) if ambiguous else words.no_margin(line=line)]
    _, inconsistent = _widen_if_inconsistent(fit, None, taps.sigma, warnings)
    return _result(
        method,
        taps,
        _Answer.of_fit(taps, fit, None),
        suspects=[],
        warnings=warnings,
        inconsistent=inconsistent,
        candidates=_candidates(taps, [geometries[i] for i in order]),
    )


def _retapped(taps: _Taps, rng: np.random.Generator) -> tuple[Array, Array]:
    """The landmarks as the same fingers might tap them again: fresh noise of ``sigma``."""
    return (
        taps.p + rng.normal(0.0, taps.sigma, taps.p.shape),
        taps.q + rng.normal(0.0, taps.sigma, taps.q.shape),
    )


def _calibrated(
    fit: EpipolarFit, covariance: Array | None, samples: Callable[[], Array]
) -> Array | None:
    """The covariance grown until its ellipse holds the bootstrap's answers (see bootstrap)."""
    answer = to_pixel(fit.epipole2)
    if covariance is None or answer is None:
        return covariance
    return covariance * bootstrap.scale(answer, covariance, samples())


def _pixel_or_nan(point: Array) -> Array:
    pixel = to_pixel(point)
    return np.full(2, np.nan) if pixel is None else pixel


# --- consistency and warnings -----------------------------------------------------------


def _widen_if_inconsistent(
    fit: EpipolarFit, covariance: Array | None, sigma: float, warnings: list[str]
) -> tuple[Array | None, bool]:
    """Taps noisier than ``sigma`` (and no culprit found): widen the ellipse, add a warning.

    Returns the covariance to report and whether the taps were inconsistent.
    """
    if consistent(fit, sigma):
        return covariance, False
    warnings.append(words.MARKS_DISAGREE)
    if covariance is not None:
        covariance = covariance * (fit.cost / sigma**2 / fit.dof)
    return covariance, True


def _suspect_warnings(taps: _Taps, suspects: list[int], fit: EpipolarFit) -> list[str]:
    off = np.abs(sampson_distances(fit.fundamental, taps.p, taps.q))
    return [words.mistapped(taps.labels[i], off[i]) for i in suspects]


def _where_warnings(taps: _Taps, e2: Array, *, behind: str, loose: bool) -> list[str]:
    """Sentences about where the seeker is relative to the buddy's photo (oriented e2).

    ``behind``: "no", "yes" (pinned down behind the buddy's camera) or "unsure"; ``loose``:
    the 95 % region is wider than a tenth of the photo.
    """
    warnings = []
    position = to_pixel(e2)
    if position is None:
        warnings.append(words.FAR_TO_THE_SIDE)
    elif behind != "no":
        if behind == "unsure":
            warnings.append(words.NOT_PINNED_DOWN)
        else:
            warnings.append(words.BEHIND_YOU)
        return warnings
    elif taps.size2 is not None:
        width, height = taps.size2
        x, y = position
        beyond = max(-x, x - width, -y, y - height)
        if beyond > 0:
            side: words.Side = (
                ("left" if x < 0 else "right")
                if max(-x, x - width) >= max(-y, y - height)
                else ("up" if y < 0 else "down")
            )
            warnings.append(words.outside_photo(beyond, side))
    if loose:
        warnings.append(words.UNCERTAIN)
    return warnings


# --- building the answer ---------------------------------------------------------------


@dataclass(frozen=True)
class _Answer:
    """What a fitted model says, before it becomes a :class:`SolveResult`."""

    epipole1: Array  # (3,) the buddy in photo 1
    epipole2: Array  # (3,) the seeker in photo 2, any sign
    covariance: Array | None  # (2, 2) px^2 of epipole2, None: no region claimed
    residuals: Array  # (N,) px
    fundamental: Array  # (3, 3); for the plane model the one it induces, [e2]x H
    homography: Array | None = None

    @classmethod
    def of_fit(cls, taps: _Taps, fit: EpipolarFit, covariance: Array | None) -> _Answer:
        distances = np.abs(sampson_distances(fit.fundamental, taps.p, taps.q))
        return cls(fit.epipole1, fit.epipole2, covariance, distances, fit.fundamental)

    @classmethod
    def of_plane(cls, taps: _Taps, plane: PlanarFit) -> _Answer:
        assert taps.epipole1 is not None
        seeker, covariance = plane.seeker(taps.epipole1, taps.sigma)
        mapped = homogeneous(taps.p) @ plane.homography.T
        transfer = np.linalg.norm(mapped[:, :2] / mapped[:, 2:] - taps.q, axis=1)
        induced = skew(seeker) @ plane.homography
        return cls(
            np.append(taps.epipole1, 1.0), seeker, covariance, transfer, induced, plane.homography
        )


def _result(
    method: Method,
    taps: _Taps,
    answer: _Answer,
    *,
    suspects: list[int],
    warnings: list[str],
    inconsistent: bool = False,
    candidates: list[Candidate] | None = None,
) -> SolveResult:
    # The buddy is seen in photo 1, so in front of the seeker's camera: that orients e1,
    # and through the landmarks e2 (in front of the buddy's camera, behind it, or sideways).
    e1 = canonical(answer.epipole1)
    e2, orientable = orient_seeker(answer.fundamental, e1, answer.epipole2, taps.p, taps.q)
    position = _pixel(e2)
    uncertainty, semi_major = _uncertainty(position, answer.covariance)
    region = quality(semi_major, taps.diagonal2)
    behind = "no"
    if position is not None and e2[2] < 0:
        # Behind the buddy: nothing to mark in the photo. Only a pinned-down, physical answer
        # may say "behind you": a loose one may have crossed infinity, and a fit that breaks
        # the oriented constraint has no reliable side (both measured on 5-landmark taps).
        behind = "yes" if orientable and region != "poor" else "unsure"
        position, uncertainty = None, Uncertainty(ellipse=None)
    grade = region
    if inconsistent or (position is None and behind != "yes"):
        grade = "poor"
    return SolveResult(
        method=method,
        landmark_count=len(taps.p),
        tap_sigma=taps.sigma,
        epipole2=position,
        epipole2_h=_unit(e2),
        epipole1=_pixel(e1),
        epipole1_h=_unit(e1),
        fundamental=None if answer.homography is not None else _matrix(answer.fundamental),
        homography=None if answer.homography is None else _matrix(answer.homography),
        candidates=candidates or [],
        uncertainty=uncertainty,
        suspect_landmarks=suspects,
        residuals=[float(r) for r in answer.residuals],
        quality=grade,
        warnings=warnings
        + _where_warnings(
            taps, e2, behind=behind, loose=semi_major is not None and region == "poor"
        ),
    )


def _candidates(taps: _Taps, geometries: list[tuple[Array, Array, Array]]) -> list[Candidate]:
    listed = []
    for rank, (buddy, seeker, f) in enumerate(geometries, 1):
        cue = assess(
            f, buddy, seeker, taps.p, taps.q, image_size1=taps.size1, image_size2=taps.size2
        )
        e1 = canonical(buddy)
        e2, _ = orient_seeker(f, e1, seeker, taps.p, taps.q)
        listed.append(
            Candidate(
                rank=rank,
                epipole1=_pixel(e1),
                epipole1_h=_unit(e1),
                epipole2=_pixel(e2),
                epipole2_h=_unit(e2),
                fundamental=_matrix(canonical_matrix(f)),
                oriented_violations=cue.oriented_violations,
                focal_lengths=cue.focal_lengths,
                phone_like=cue.phone_like,
            )
        )
    return listed


def _uncertainty(
    e2: tuple[float, float] | None, covariance: Array | None
) -> tuple[Uncertainty, float | None]:
    if e2 is None or covariance is None or not np.all(np.isfinite(covariance)):
        return Uncertainty(ellipse=None), None
    centre, axes, angle = ellipse(np.array(e2), covariance)
    cov = (
        (float(covariance[0, 0]), float(covariance[0, 1])),
        (float(covariance[1, 0]), float(covariance[1, 1])),
    )
    return Uncertainty(
        ellipse=Ellipse(center=centre, axes=axes, angle_deg=angle), covariance=cov
    ), axes[0]


def _pixel(point: Array) -> tuple[float, float] | None:
    pixel = to_pixel(point)
    return None if pixel is None else (float(pixel[0]), float(pixel[1]))


def _unit(point: Array) -> tuple[float, float, float]:
    """A homogeneous point at unit norm, its sign (orientation) kept."""
    x, y, w = point / np.linalg.norm(point)
    return float(x), float(y), float(w)


def _matrix(matrix: Array) -> Matrix:
    first, second, third = (_homogeneous_row(row) for row in matrix)
    return first, second, third


def _homogeneous_row(row: Array) -> tuple[float, float, float]:
    return float(row[0]), float(row[1]), float(row[2])
