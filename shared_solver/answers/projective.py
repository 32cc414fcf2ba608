"""Answers from the paper's projective geometry: any two cameras, nothing known about them.

| given                   | landmarks | method                                     |
|-------------------------|-----------|--------------------------------------------|
| both friends (e1, e2)   | >= 3      | ``two_epipoles``                           |
| friend 2 (e1)           | 4         | ``conic`` (a curve, not a point)           |
| friend 2 (e1)           | 5         | ``five_point_epipole`` or ``planar``       |
| friend 2 (e1)           | >= 6      | ``least_squares_epipole`` or ``planar``    |
| a line through friend 2 | >= 6      | ``six_point_line`` (ranked candidates)     |
| nothing                 | 7 / >= 8  | ``seven_point`` / ``eight_point`` (OpenCV) |
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .. import linalg, words
from ..errors import Reason, WarningCode
from ..estimation import bootstrap
from ..estimation.epipolar_fit import EpipolarFit, fit_epipolar, fit_two_epipoles
from ..estimation.mistaps import find_mistaps, refit
from ..estimation.planar import PlanarFit, coplanar_fit
from ..estimation.plausibility import assess
from ..estimation.uncertainty import chi2_quantile, consistent, covering
from ..minimal.conic import conic_from_cross_ratio
from ..minimal.five_point_linear import fundamental_with_epipole
from ..minimal.seven_point import seven_point_roots
from ..minimal.six_point_line import six_point_line_roots
from ..minimal.two_epipoles import fundamental_between
from ..projective import (
    Array,
    canonical_matrix,
    far_pixel,
    hartley_normaliser,
    homogeneous,
    to_pixel,
    transform,
)
from ..refusal import SolverError
from ..result import Method, SolveResult, SolverWarning
from .building import (
    Answer,
    Geometry,
    calibrated,
    candidates,
    matrix,
    pixel,
    pixel_or_nan,
    result,
    suspect_warnings,
    unit,
    unknown_cameras,
    widen_if_inconsistent,
)
from .request import Request

# The plane model's answer agrees with the general one when their gap is within this
# chi-square (2 dof, 0.99) of what the general one's extra spread explains.
_PLANE_AGREES = chi2_quantile(0.99, 2)


def conic(request: Request) -> SolveResult:
    """Paper 3.1: four landmarks and friend 2 put friend 1 on a curve."""
    taps = request.taps
    assert taps.epipole1 is not None
    return SolveResult(
        method="conic",
        cameras=list(unknown_cameras(request)),
        landmark_count=len(taps),
        tap_sigma=request.sigma,
        epipole2=None,
        epipole2_h=None,
        epipole1=pixel(np.append(taps.epipole1, 1.0)),
        epipole1_h=unit(np.append(taps.epipole1, 1.0)),
        conic2=matrix(conic_through(request)),
        residuals=[0.0] * len(taps),
        quality="fair",
        warnings=[SolverWarning.of(WarningCode.ON_THE_CURVE)],
    )


def conic_through(request: Request) -> Array:
    """(3, 3) the curve of paper 3.1 through the first four landmarks, in photo-2 pixels."""
    taps = request.taps
    assert taps.epipole1 is not None
    p, q = taps.p[:4], taps.q[:4]
    t1, t2 = hartley_normaliser(p), hartley_normaliser(q)
    curve = conic_from_cross_ratio(
        t1 @ homogeneous(taps.epipole1[None])[0],
        transform(t1, homogeneous(p)),
        transform(t2, homogeneous(q)),
    )
    return canonical_matrix(t2.T @ curve @ t2)


def friend2_marked(request: Request) -> SolveResult:
    """The paper's case: friend 2 tapped in photo 1, five or more landmarks."""
    taps = request.taps
    assert taps.epipole1 is not None
    fit = fit_epipolar(
        taps, fundamental_with_epipole(np.append(taps.epipole1, 1.0), taps.p, taps.q)
    )
    suspects: list[int] = []
    warnings: list[SolverWarning] = []
    if not consistent(fit):
        found = find_mistaps(taps, use_friend2=True) if len(taps) >= 7 else None
        if found is not None:
            suspects, fit = found
            warnings += suspect_warnings(request, suspects, fit.fundamental)
    used = taps.without(suspects)
    covariance = fit.covariance2
    if len(used) == 5:  # minimal: first order is too optimistic near degenerate layouts
        covariance = calibrated(
            fit.epipole2, covariance, lambda: bootstrap.five_point_samples(used)
        )
    plane = coplanar_fit(used)
    if plane is not None:
        planar = _on_the_plane(request, plane, fit.epipole2, covariance)
        if planar is not None:
            answer = result("planar", request, planar, suspects=suspects, warnings=warnings)
            # A plane that puts friend 1 behind friend 2 or nowhere does not replace a point.
            if answer.epipole2 is not None:
                return answer
    method: Method = "five_point_epipole" if len(used) == 5 else "least_squares_epipole"
    return _fitted(method, request, fit, covariance, suspects=suspects, warnings=warnings)


def _on_the_plane(
    request: Request, plane: PlanarFit, general: Array, covariance: Array | None
) -> Answer | None:
    """The plane model's answer ``e2 = H e1``, or None where the general one disagrees.

    A few landmarks off a plane can fit one within tap noise by chance, and then the
    plane's answer is off by more than its region says. So the plane is used only where the
    general answer (3,) agrees with it (their gap within what the general one's extra
    spread explains: a Hausman test), and its region also holds the general answer's
    region (``covariance``, (2, 2)): a sharper point on a plane, never a region the general
    answer would have held the truth outside of.
    """
    answer = Answer.of_plane(request, plane)
    position, centre = to_pixel(answer.epipole2), far_pixel(general)
    own = answer.covariance
    if position is None or centre is None or own is None or covariance is None:
        return None
    if not (np.all(np.isfinite(covariance)) and np.all(np.isfinite(own))):
        return None
    gap = centre - position
    extra: Array = covariance - own
    try:
        if np.linalg.eigvalsh(extra)[0] <= 0.0:
            extra = covariance
        if float(gap @ linalg.solve(extra, gap)) > _PLANE_AGREES:
            return None
        region = covering((position, own), (centre, covariance))
    except linalg.LinAlgError:
        return None
    return replace(answer, covariance=region)


def both_epipoles(request: Request) -> SolveResult:
    """Both friends marked each other: F from both marks and three or more landmarks."""
    taps = request.taps
    assert taps.epipole1 is not None
    assert taps.epipole2 is not None
    e1h, e2h = np.append(taps.epipole1, 1.0), np.append(taps.epipole2, 1.0)
    fit = fit_two_epipoles(taps, fundamental_between(e1h, e2h, taps.p, taps.q))
    warnings: list[SolverWarning] = []
    return _fitted("two_epipoles", request, fit, fit.covariance2, suspects=[], warnings=warnings)


def line_through_friend2(request: Request) -> SolveResult:
    """Paper 3.3: the cubic's real roots on the first six landmarks, refined over all."""
    taps = request.taps
    assert taps.line1 is not None
    geometries = six_point_line_roots(taps.line1, taps.p[:6], taps.q[:6])
    if not geometries:
        raise SolverError(Reason.LINE_FITS_NOTHING)
    return _likeliest(request, "six_point_line", geometries, minimal=len(taps) == 6)


def landmarks_only(request: Request) -> SolveResult:
    """No tap on friend 2: the classical 7- and 8-point methods (OpenCV), refined over all taps."""
    taps = request.taps
    if coplanar_fit(taps) is not None:
        raise SolverError(Reason.ONE_SURFACE_UNMARKED)
    if len(taps) == 7:
        geometries = seven_point_roots(taps.p, taps.q)
        if not geometries:
            raise SolverError(Reason.SEVEN_FIT_NOTHING)
        return _likeliest(request, "seven_point", geometries, minimal=True)
    suspects: list[int] = []
    warnings: list[SolverWarning] = []
    fit = refit(taps, use_friend2=False)
    if not consistent(fit) and len(taps) >= 9:
        found = find_mistaps(taps, use_friend2=False)
        if found is not None:
            suspects, fit = found
            warnings += suspect_warnings(request, suspects, fit.fundamental)
    covariance = fit.covariance2
    if len(taps) - len(suspects) == 8:  # one more than minimal: first order measured optimistic
        used = taps.without(suspects)
        covariance = calibrated(
            fit.epipole2,
            covariance,
            lambda: bootstrap.resolved_samples(
                used, lambda again: pixel_or_nan(refit(again, use_friend2=False).epipole2)
            ),
        )
    return _fitted("eight_point", request, fit, covariance, suspects=suspects, warnings=warnings)


def _fitted(
    method: Method,
    request: Request,
    fit: EpipolarFit,
    covariance: Array | None,
    *,
    suspects: list[int],
    warnings: list[SolverWarning],
) -> SolveResult:
    """One refined fit's answer, its region (2, 2) px^2 widened (with a warning) where the
    taps disagree with it more than their precision says."""
    covariance, inconsistent = widen_if_inconsistent(fit, covariance, warnings)
    return result(
        method,
        request,
        Answer.of_fit(request, fit, covariance),
        suspects=suspects,
        warnings=warnings,
        inconsistent=inconsistent,
    )


def _likeliest(
    request: Request, method: Method, geometries: list[Geometry], *, minimal: bool
) -> SolveResult:
    """Several geometries fit: rank them by plausibility, answer with the first, list all.

    With more landmarks than the minimum each candidate is first refined over all of them,
    and a spurious root stops fitting. No 95 % region is claimed for these methods: measured
    on facing scenes, neither first order nor a bootstrap held the truth often enough (the
    noise can carry the answer into another root's basin), so the answer is graded 'poor'
    and says what would make it reliable.
    """
    taps = request.taps
    use_friend2 = taps.line1 is not None
    fits: list[EpipolarFit] | None = None
    if not minimal:
        fits = [fit_epipolar(taps, f, use_friend2=use_friend2) for _, _, f in geometries]
        geometries = [(f.epipole1, f.epipole2, f.fundamental) for f in fits]
    fit_ok = [True] * len(geometries) if fits is None else [consistent(f) for f in fits]
    cues = [
        assess(f, e1, e2, taps.p, taps.q, image_size1=request.size1, image_size2=request.size2)
        for e1, e2, f in geometries
    ]
    order = sorted(
        range(len(geometries)),
        key=lambda i: (cues[i].hard_cues(), not fit_ok[i], cues[i].focal_deviation),
    )
    top = order[0]
    fit = (
        fits[top]
        if fits is not None
        else fit_epipolar(taps, geometries[top][2], use_friend2=use_friend2)
    )
    ambiguous = sum(cues[i].hard_cues() == cues[top].hard_cues() and fit_ok[i] for i in order) > 1
    marked: words.Marked = "line" if taps.line1 is not None else "none"
    code = WarningCode.AMBIGUOUS if ambiguous else WarningCode.NO_MARGIN
    warnings = [SolverWarning.of(code, marked=marked)]
    _, inconsistent = widen_if_inconsistent(fit, None, warnings)
    return result(
        method,
        request,
        Answer.of_fit(request, fit, None),
        suspects=[],
        warnings=warnings,
        inconsistent=inconsistent,
        candidates=candidates(request, [geometries[i] for i in order], [cues[i] for i in order]),
    )
