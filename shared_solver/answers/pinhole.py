"""Answers that use what a phone camera is: square pixels, a centred principal point, and a
prior on the focal length (:mod:`..estimation.camera`).

| given                   | landmarks | method                   | starts from                   |
|-------------------------|-----------|--------------------------|-------------------------------|
| both friends (e1, e2)   | >= 1      | ``pinhole_two_epipoles`` | one landmark and both marks   |
| friend 2 (e1)           | >= 3      | ``pinhole_epipole``      | three landmarks and friend 2  |
| a line through friend 2 | >= 6      | ``pinhole_line``         | the cubic's roots (paper 3.3) |
| nothing                 | >= 7      | ``pinhole_landmarks``    | the 7- or 8-point solutions   |

Each is the maximum a posteriori fit over every tap (:mod:`..estimation.pinhole`),
started from every pose the exact solvers allow and kept where the taps fit best. The
answer is used only where the taps agree with the model (a chi-square test on its
residuals); otherwise these functions return None and ``solve`` answers with the
projective geometry instead, saying so.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from .. import linalg, words
from ..errors import WarningCode
from ..estimation import bootstrap
from ..estimation.epipolar_fit import fit_epipolar
from ..estimation.mistaps import refit
from ..estimation.pinhole.fit import PinholeFit, fit_pinhole
from ..estimation.pinhole.mistaps import find_pinhole_mistaps
from ..estimation.pinhole.model import PinholeModel
from ..estimation.pinhole.pose import Poses
from ..estimation.pinhole.starts import (
    behind,
    fundamental_starts,
    marked_starts,
    unmarked_starts,
    wider_marked_starts,
)
from ..estimation.taps import Taps
from ..estimation.uncertainty import CHI2_2D, chi2_quantile, consistent
from ..minimal.five_point_linear import fundamental_with_epipole
from ..minimal.seven_point import seven_point_roots
from ..minimal.six_point_line import six_point_line_roots
from ..projective import Array, far_pixel, inside, to_pixel
from ..result import Method, SolveResult, SolverWarning, Uncertainty
from .building import (
    Answer,
    calibrated,
    pinhole_candidates,
    result,
    suspect_warnings,
    widen_if_inconsistent,
)
from .projective import conic_through
from .request import Request

# Starts whose score is within this of the best are refined too (chi-square units: a
# start this much worse can still be the right pose once refined).
_REFINE_MARGIN = 9.0
# Refined fits within this cost of the best, with friend 1 elsewhere, make the answer
# ambiguous (a difference of 4 is two sigmas of evidence).
_AMBIGUOUS_COST = 4.0
# Fits within this cost of each other tie: nothing the taps say tells them apart.
_TIE_COST = 1e-6
# Where along a drawn line (its part inside photo 1) friend 2 is tried, as fractions.
_ALONG = (0.1, 0.3, 0.5, 0.7, 0.9)
# Mis-taps are looked for from this many landmarks: six give the projective check that the
# camera model is not what disagrees one degree of freedom, and the camera model's own
# consensus two to spare.
_MISTAPS_FROM = 6
# At most this many degrees of freedom to spare, first order was measured too optimistic
# (three or four landmarks and friend 2): the region is calibrated by a bootstrap.
BOOTSTRAP_DOF = 1
# Fits that put friend 1 closer than this many of their own sigmas are the same answer.
_SAME_ANSWER_SIGMAS = 3.0
# The camera model is judged not to fit the taps when its fit's chi-square is beyond this
# quantile: about one honest search in ten thousand is then told its photos do not look
# like two phone photos (0.99 told one in a hundred; measured in docs/solver-benchmark.md,
# section 8). A wrong model still shows: a stretched photo is caught from five landmarks.
LEVEL = 0.9999
# The compass headings are judged to contradict the landmarks beyond this quantile: one
# honest search in a hundred loses them, and answers as it would without a compass.
HEADING_LEVEL = 0.99
# Starts of the wider search refined at most (it runs when no first start fits).
_WIDER_REFINED = 12
# Warnings of where friend 1 is: an answer with no position keeps none of them.
_WHERE = frozenset(
    {
        WarningCode.OUTSIDE_PHOTO,
        WarningCode.FAR_TO_THE_SIDE,
        WarningCode.BEHIND_YOU,
        WarningCode.NOT_PINNED_DOWN,
        WarningCode.UNCERTAIN,
    }
)


@dataclass(frozen=True)
class CameraAnswer:
    """The camera model's answer, and whether the taps agree with the model.

    Attributes:
        result: the answer (None: no pose of two phone cameras fits at all).
        agrees: its fit passed the chi-square test at ``LEVEL``; when it did not, ``solve``
            weighs it against the projective answer (:mod:`.disagreement`).
        heading_agrees: the compass headings in the fit (if any) passed their own test
            (:func:`_heading_agrees`); when they did not, ``solve`` answers without them.
    """

    result: SolveResult | None
    agrees: bool
    heading_agrees: bool = True


def friend2_marked(request: Request) -> CameraAnswer:
    """Friend 2 marked as a point (and maybe friend 1 too), one or more landmarks."""
    taps, priors = request.taps, request.priors
    assert priors is not None
    assert taps.epipole1 is not None
    model = PinholeModel(taps, priors)
    # A landmark near the line between the friends has no sure side: noise can put it
    # behind a camera in the scene's pose, whose start then scores far worse and is left
    # out, and the pose kept puts friend 1 behind friend 2 ("behind you", with a sure region,
    # where taps fit exactly: one landmark and gravity, three and the EXIF focal). So when no
    # fit is physical, every start is refined, and neither is claimed alone (_likeliest,
    # _near).
    fits = _refined(
        model,
        marked_starts(model),
        wider=lambda: wider_marked_starts(model),
        physical=lambda fit: _physical(model, fit),
    )
    if taps.gravity is not None:
        # Gravity leaves one landmark two turns that fit exactly: the one that puts the
        # landmarks in front of both phones, and friend 1 in front of friend 2, is the scene.
        fits = [fit for fit in fits if _physical(model, fit)] or fits
    if not fits:
        return CameraAnswer(None, agrees=False)
    fit = _likeliest(fits, request.size2)
    if not _heading_agrees(model, fit):
        return CameraAnswer(None, agrees=False, heading_agrees=False)
    suspects: list[int] = []
    warnings: list[SolverWarning] = []
    if not consistent(fit) and len(taps) >= _MISTAPS_FROM and _projective_disagrees(taps):
        # The taps disagree whatever the cameras: look for the landmark to blame.
        found = find_pinhole_mistaps(model)
        if found is not None:
            suspects, fit = found
            warnings += suspect_warnings(request, suspects, fit.fundamental)
    both = taps.epipole2 is not None
    # Tested where the projective geometry can answer too (a point or, from four
    # landmarks and friend 2, the curve), and wherever gravity is in the fit (without it
    # the landmarks may answer alone).
    tested = len(taps) >= (3 if both else 4) or taps.gravity is not None
    agrees = consistent(fit, LEVEL) or not tested
    others, alike = _near(fit, fits)
    covariance = fit.covariance2
    if fit.dof <= BOOTSTRAP_DOF:
        used = taps.without(suspects)
        covariance = calibrated(
            fit.epipole2, covariance, lambda: bootstrap.pinhole_samples(fit, used, priors)
        )
    covariance, inconsistent = widen_if_inconsistent(fit, covariance, warnings)
    covariance = _holding(covariance, fit, alike)
    method: Method = "pinhole_two_epipoles" if both else "pinhole_epipole"
    answer = Answer.of_pinhole(request, fit, covariance, orientable=_orientable(model, fit))
    if len(taps) == 4 and not both:
        answer = _with_conic(answer, conic_through(request))
    if not others:
        return CameraAnswer(
            result(
                method,
                request,
                answer,
                suspects=suspects,
                warnings=warnings,
                inconsistent=inconsistent,
            ),
            agrees,
        )
    return CameraAnswer(_ambiguous(request, model, method, fit, others, warnings=warnings), agrees)


def line_through_friend2(request: Request) -> CameraAnswer:
    """A line through friend 2 and six or more landmarks: the cubic's roots, ranked by how
    well each fits a pair of phone cameras once refined over every tap."""
    taps, priors = request.taps, request.priors
    assert priors is not None
    assert taps.line1 is not None
    roots = six_point_line_roots(taps.line1, taps.p[:6], taps.q[:6])
    model = PinholeModel(taps, priors)
    fundamentals = [f for _, _, f in roots]
    answer = _from_roots(
        request, model, "pinhole_line", fundamentals, np.array(_friend2_places(roots))
    )
    unpinned = answer is not None and _unpinned(answer)
    if (answer is None or unpinned) and request.size1 is not None:
        # No pose near the roots pins friend 1 down: try friend 2 spread along the line too.
        along = np.array(_along(taps.line1, request.size1))
        if len(along):
            starts = unmarked_starts(model, fundamentals, along)
            found = _from_starts(request, model, "pinhole_line", starts)
            if found is not None and (found[1] or answer is None):
                answer = found[0] if found[1] else _unphysical(found[0])
    return CameraAnswer(answer, agrees=answer is not None)


def landmarks_only(request: Request) -> CameraAnswer:
    """No mark of friend 2: seven or more landmarks, the 7- or 8-point solutions ranked by
    how well each fits a pair of phone cameras once refined."""
    taps, priors = request.taps, request.priors
    assert priors is not None
    if len(taps) == 7:
        roots = seven_point_roots(taps.p, taps.q)
    else:
        fit = refit(taps, use_friend2=False)
        roots = [(fit.epipole1, fit.epipole2, fit.fundamental)]
    model = PinholeModel(taps, priors)
    fundamentals = [f for _, _, f in roots]
    answer = _from_roots(
        request, model, "pinhole_landmarks", fundamentals, np.array(_friend2_places(roots))
    )
    return CameraAnswer(answer, agrees=answer is not None)


def _from_roots(
    request: Request,
    model: PinholeModel,
    method: Method,
    fundamentals: list[Array],
    friend2_places: Array,
) -> SolveResult | None:
    """The answer from projective solutions ``fundamentals`` (3, 3), read as poses first.

    Only when none of those refines to an orientable fit (every landmark in front of both
    cameras) that puts friend 1 in front of friend 2 are the three-landmark solver's poses
    added, with friend 2 at each solution's own ``friend2_places`` (B, 2): with noisy taps a
    projective solution can be far from any pair of phone cameras while it puts friend 2
    near the right place. Most taps need only the first, cheaper, search (measured: the
    same accuracy, coverage and ranking, docs/geometry.md). When neither finds an orientable
    fit, the answer is not pinned down (:func:`_unphysical`).
    """
    first = _from_starts(request, model, method, fundamental_starts(model, fundamentals))
    if first is not None and first[0].epipole2 is not None and first[1]:
        return first[0]
    wider = _from_starts(
        request, model, method, unmarked_starts(model, fundamentals, friend2_places)
    )
    found = wider if wider is not None else first
    if found is None:
        return None
    if not found[1] and first is not None and first[1]:
        found = first  # orientable, though friend 1 is behind friend 2
    answer, orientable = found
    return answer if orientable else _unphysical(answer)


def _from_starts(
    request: Request, model: PinholeModel, method: Method, starts: list[tuple[float, Poses]]
) -> tuple[SolveResult, bool] | None:
    """The best of ``starts`` refined (a line or nothing marked) as the answer, and whether
    its fit is orientable (every landmark in front of both cameras: :func:`_orientable`);
    None when no fit agrees with the taps."""
    fits = _refined(model, starts)
    if not fits or not consistent(fits[0], LEVEL):
        return None
    fit = _likeliest(fits, request.size2)
    orientable = _orientable(model, fit)
    others, alike = _near(fit, fits)
    warnings: list[SolverWarning] = []
    if others:
        return _ambiguous(request, model, method, fit, others, warnings=warnings), orientable
    covariance, inconsistent = widen_if_inconsistent(fit, fit.covariance2, warnings)
    covariance = _holding(covariance, fit, alike)
    answer = result(
        method,
        request,
        Answer.of_pinhole(request, fit, covariance, orientable=orientable),
        suspects=[],
        warnings=warnings,
        inconsistent=inconsistent,
    )
    return answer, orientable


def _unpinned(answer: SolveResult) -> bool:
    return any(warning.code is WarningCode.NOT_PINNED_DOWN for warning in answer.warnings)


def _unphysical(answer: SolveResult) -> SolveResult:
    """An answer whose fit puts a landmark behind a camera, as not pinned down: no position
    and no region. The taps fit it, but no real pair of cameras; on the benchmark's phone
    scenes (7 landmarks, or 6 and a line, 3 and 8 px) 21 of 54 such answers put friend 1
    far outside their region (docs/geometry.md)."""
    kept = [
        warning
        for warning in answer.warnings
        if warning.code not in _WHERE and warning.code is not WarningCode.AMBIGUOUS
    ]
    return answer.model_copy(
        update={
            "epipole2": None,
            "uncertainty": Uncertainty(ellipse=None),
            "candidates": [],
            "quality": "poor",
            "warnings": [*kept, SolverWarning.of(WarningCode.NOT_PINNED_DOWN)],
        }
    )


def _friend2_places(roots: list[tuple[Array, Array, Array]]) -> list[Array]:
    """Friend 2's pixel in photo 1 of each projective solution (e1, e2, F) that has one."""
    return [e1[:2] / e1[2] for e1, _, _ in roots if abs(e1[2]) > 1e-12 * linalg.norm(e1)]


def _along(line: Array, size: tuple[float, float]) -> list[Array]:
    """Pixels spread along the part of ``line`` (a x + b y + c = 0) inside a photo of
    ``size``: where friend 2 may be, to start from."""
    a, b, c = line
    width, height = size
    ends = []
    for x in (0.0, width):  # where the line crosses the left and right edges
        if b != 0 and 0 <= (y := -(a * x + c) / b) <= height:
            ends.append((x, y))
    for y in (0.0, height):  # ... the top and bottom edges
        if a != 0 and 0 <= (x := -(b * y + c) / a) <= width:
            ends.append((x, y))
    if len(ends) < 2:
        return []
    start, end = np.array(ends[0]), np.array(ends[-1])
    return [start + fraction * (end - start) for fraction in _ALONG]


def _projective_disagrees(taps: Taps) -> bool:
    """Whether the taps also disagree with any two projective cameras (chi-square test on
    the projective fit): then a landmark is to blame, not the camera model."""
    assert taps.epipole1 is not None
    start = fundamental_with_epipole(np.append(taps.epipole1, 1.0), taps.p, taps.q)
    return not consistent(fit_epipolar(taps, start))


def _refined(
    model: PinholeModel,
    starts: list[tuple[float, Poses]],
    *,
    wider: Callable[[], list[tuple[float, Poses]]] | None = None,
    physical: Callable[[PinholeFit], bool] | None = None,
) -> list[PinholeFit]:
    """The best start refined, and any other start close enough to it; all of them when
    those do not fit the taps (a start's score is read at the priors' focal lengths, and a
    poor-looking start may be the right basin), then the best few of the ``wider`` search's;
    and with ``physical``, all of them when no fit so far is. Best fit first."""
    fits: list[PinholeFit] = []
    refined = 0  # starts refined, best first
    if starts:
        best = starts[0][0]
        refined = sum(1 for score, _ in starts if score <= best + _REFINE_MARGIN)
        fits = [fit_pinhole(model, pose) for _, pose in starts[:refined]]
        if not any(consistent(fit, LEVEL) for fit in fits):
            fits += [fit_pinhole(model, pose) for _, pose in starts[refined:]]
            refined = len(starts)
    if wider is not None and not any(fit.usable and consistent(fit, LEVEL) for fit in fits):
        fits += [fit_pinhole(model, pose) for _, pose in wider()[:_WIDER_REFINED]]
    if physical is not None and not any(fit.usable and physical(fit) for fit in fits):
        fits += [fit_pinhole(model, pose) for _, pose in starts[refined:]]
    return sorted((fit for fit in fits if fit.usable), key=lambda fit: fit.cost)


def _orientable(model: PinholeModel, fit: PinholeFit) -> bool:
    """Whether every landmark is in front of both cameras (a physical geometry)."""
    return int(behind(fit.pose, model)[0]) == 0


def _physical(model: PinholeModel, fit: PinholeFit) -> bool:
    """Every landmark in front of both cameras, and friend 1 in front of friend 2's."""
    return _orientable(model, fit) and bool(fit.epipole2[2] > 0)


def _heading_agrees(model: PinholeModel, fit: PinholeFit) -> bool:
    """Whether the compass headings fit what the other taps say of the turn about the
    vertical: their residual's square over its variance once the fit has leaned on it,
    ``r^2 / (1 - h)`` with ``h`` its leverage (the test of leaving it out, to first order),
    against the chi-square (1) at ``HEADING_LEVEL``. True without headings."""
    row = model.compass_row
    if row is None:
        return True
    residual, _ = model.residuals(fit.pose)
    gradient = fit.jacobian[row]
    leverage = float(gradient @ fit.covariance @ gradient)
    return bool(residual[row] ** 2 <= chi2_quantile(HEADING_LEVEL, 1) * max(1.0 - leverage, 0.0))


def _likeliest(fits: list[PinholeFit], size2: tuple[float, float] | None) -> PinholeFit:
    """The best fit, or among those about as good (ambiguous ones) the best that puts
    friend 1 in front of friend 2's camera, and of those the best that puts friend 1 inside
    photo 2 (of ``size2``, when given): friend 2 photographed friend 1's side.

    The second rule matters where the taps cannot choose, as with one landmark and gravity
    (two turns fit exactly): on the benchmark's phone scenes the turn it marks was the
    nearer the truth in 18 of 19 such answers, against 11 of 18 by cost alone
    (docs/geometry.md). The answer stays marked ambiguous, every fit listed."""
    near = [fit for fit in fits if fit.cost <= fits[0].cost + _AMBIGUOUS_COST]
    in_front = [fit for fit in near if fit.epipole2[2] > 0] or near
    if len(in_front) == 1 or size2 is None:
        return in_front[0]
    inside = [fit for fit in in_front if _inside(fit.epipole2, size2)]
    eligible = inside or in_front
    # Fits that tie exactly (minimal taps: every root fits them, at the same prior cost) are
    # ordered by rounding alone, which a scaled photo changes: the one nearer photo 2's
    # centre goes first, where friend 2 aimed.
    tied = [fit for fit in eligible if fit.cost <= eligible[0].cost + _TIE_COST]
    if len(tied) == 1:
        return tied[0]
    centre = np.array(size2) / 2.0
    return min(tied, key=lambda fit: _off_centre(fit.epipole2, centre))


def _off_centre(friend1: Array, centre: Array) -> float:
    """How far the homogeneous pixel ``friend1`` (3,) lies from ``centre`` (2,), px."""
    pixel = far_pixel(friend1)  # however far: a scaled photo must order ties alike
    return float("inf") if pixel is None else float(np.hypot(*(pixel - centre)))


def _inside(friend1: Array, size: tuple[float, float]) -> bool:
    """Whether the homogeneous pixel ``friend1`` (3,) lies in front, in a photo of ``size``."""
    pixel = to_pixel(friend1)
    return bool(friend1[2] > 0 and pixel is not None and inside(pixel[None], size)[0])


def _near(fit: PinholeFit, fits: list[PinholeFit]) -> tuple[list[PinholeFit], list[PinholeFit]]:
    """The other refined fits that explain the taps about as well as ``fit``, as
    ``(rivals, alike)``: rivals put friend 1 elsewhere (beyond ``_SAME_ANSWER_SIGMAS`` of
    ``fit``'s first-order region, or where it cannot tell); alike ones close enough to be
    the same answer."""
    covariance = fit.covariance2
    position = fit.epipole2
    rivals, alike = [], []
    for other in fits:
        if other is fit or other.cost > fit.cost + _AMBIGUOUS_COST:
            continue
        if covariance is not None and position[2] > 0 and other.epipole2[2] > 0:
            offset = other.epipole2[:2] / other.epipole2[2] - position[:2] / position[2]
            if _squared_sigmas(offset, covariance) <= _SAME_ANSWER_SIGMAS**2:
                alike.append(other)
                continue
        rivals.append(other)
    return rivals, alike


def _holding(covariance: Array | None, fit: PinholeFit, alike: list[PinholeFit]) -> Array | None:
    """``covariance`` grown until its 95 % region holds friend 1 where each of ``alike`` puts
    them: the taps cannot tell those fits from ``fit``, so neither may the region. Without
    it, two turns that fit one landmark exactly, 2.4 to 3 sigmas apart, were one answer
    whose region held only one (tests/solver/test_gravity.py)."""
    position = None if not alike else far_pixel(fit.epipole2)
    if covariance is None or position is None:
        return covariance
    factor = 1.0
    for other in alike:
        elsewhere = far_pixel(other.epipole2)
        if elsewhere is None:
            continue
        distance = _squared_sigmas(elsewhere - position, covariance)
        if np.isfinite(distance):  # a singular region cannot say how far: left as it is
            factor = max(factor, distance / CHI2_2D)
    return covariance * factor


def _squared_sigmas(offset: Array, covariance: Array) -> float:
    """``offset`` (2,) px in squared sigmas of ``covariance`` (2, 2) (Mahalanobis); infinite
    when the covariance is singular."""
    try:
        return float(offset @ linalg.solve(covariance, offset))
    except linalg.LinAlgError:
        return np.inf


def _ambiguous(
    request: Request,
    model: PinholeModel,
    method: Method,
    fit: PinholeFit,
    others: list[PinholeFit],
    *,
    warnings: list[SolverWarning],
) -> SolveResult:
    """Several poses fit: the likeliest is marked, every one is listed, no region claimed."""
    marked: words.Marked = (
        "point"
        if request.taps.epipole1 is not None
        else "line"
        if request.taps.line1 is not None
        else "none"
    )
    return result(
        method,
        request,
        Answer.of_pinhole(request, fit, None, orientable=_orientable(model, fit)),
        suspects=[],
        warnings=[*warnings, SolverWarning.of(WarningCode.AMBIGUOUS, marked=marked)],
        inconsistent=True,
        candidates=pinhole_candidates(request, [fit, *others]),
    )


def _with_conic(answer: Answer, conic: Array) -> Answer:
    return replace(answer, conic=conic)
