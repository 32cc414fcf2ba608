"""``solve``: the one entry point. It picks the route from what the two people tapped and
what is known about their cameras.

With a camera model for both photos (``camera1``/``camera2``: a phone, or a known focal
length) the answer uses what a phone photo is (:mod:`.answers.pinhole`), and needs fewer
landmarks; without one it is the paper's projective geometry (:mod:`.answers.projective`).

| given                   | with a camera model | without      | answer                  |
|-------------------------|---------------------|--------------|-------------------------|
| both friends (e1, e2)   | >= 1 landmark       | >= 3         | position                |
| friend 2 (e1)           | >= 3                | 4: curve, 5+ | position (+ curve at 4) |
| a line through friend 2 | >= 6                | >= 6         | position, candidates    |
| nothing                 | >= 7                | >= 7         | position, candidates    |

The camera-aware answer is used only where the taps agree with it; otherwise, if the
projective geometry can answer, it does, and a warning says so. Every tap is noisy (each
with its own precision, ``tap_sigma`` by default), the friends' marks included: with more
than the minimum the answer is the maximum-likelihood fit over all taps. It comes with
per-landmark residuals, suspects, a quality grade, sentences to act on, and a 95 % ellipse
wherever one was measured to hold the truth about 95 % of the time.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from pydantic import ValidationError

from . import validation
from .answers import disagreement, level, pinhole, projective
from .answers.request import Request
from .errors import Marks, Reason, WarningCode
from .estimation.camera import Camera
from .estimation.taps import Gravity, Heading, Taps
from .projective import homogeneous
from .refusal import SolverError
from .result import SolveResult, SolverWarning

# Two taps closer than this many tap sigmas are the same place; landmarks within it of one
# line are collinear: degenerate at the precision of a finger.
_SAME_PLACE_SIGMAS = 0.5

CameraInput = Camera | Mapping[str, Any] | str | None
# The cameras named by a word alone, built once (a Camera is immutable).
_UNKNOWN = Camera()
_BY_KIND = {"unknown": _UNKNOWN, "phone": Camera.phone()}


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
    camera1: CameraInput = None,
    camera2: CameraInput = None,
    points1_sigma: ArrayLike | None = None,
    points2_sigma: ArrayLike | None = None,
    epipole1_sigma: ArrayLike | None = None,
    epipole2_sigma: ArrayLike | None = None,
    fundamental_covariance: bool = False,
    gravity1: ArrayLike | None = None,
    gravity2: ArrayLike | None = None,
    gravity_sigma_deg: float = 1.0,
    gravity1_sigma_deg: float | None = None,
    gravity2_sigma_deg: float | None = None,
    heading1: float | None = None,
    heading2: float | None = None,
    heading_sigma_deg: float = 15.0,
    heading1_sigma_deg: float | None = None,
    heading2_sigma_deg: float | None = None,
) -> SolveResult:
    """Where friend 1 stands in friend 2's photo, from whatever the two people tapped.

    The route follows from the input (module docstring): ``conic`` is paper 3.1,
    ``five_point_epipole`` 3.2, ``six_point_line`` 3.3, ``two_epipoles`` the introduction's
    pencil homography; with more landmarks, maximum likelihood over every tap (Sampson
    distances, Hartley & Zisserman 11.4.3), and ``planar`` is ``e2 = H e1``; the
    ``pinhole_*`` methods add what a phone camera is (docs/geometry.md).

    Args:
        points1: (N, 2) landmarks in photo 1 (friend 1's), pixels, x right, y down.
        points2: (N, 2) the same landmarks, same order, in photo 2 (friend 2's).
        epipole1: (2,) where friend 1 tapped friend 2 in photo 1.
        epipole2: (2,) where friend 2 tapped friend 1 in photo 2 (both see each other);
            needs ``epipole1``.
        epipolar_line1: (3,) line ``a x + b y + c = 0`` in photo 1 through friend 2, when
            friend 1 can only say "somewhere along here"; excludes ``epipole1``.
        tap_sigma: standard deviation of a tap, px per axis, for every tap whose own
            precision is not given.
        image_size1, image_size2: (width, height) of the photos, px; needed for a camera
            model, and used for plausibility, quality and "outside the photo" warnings.
        landmark_ids: the numbers people see on the landmarks, for messages (default 1..N).
        camera1, camera2: what is known about each photo's camera: a :class:`Camera`, its
            JSON (``{"kind": "phone"}``, ``{"kind": "known_focal", "focal_35mm": 26}``),
            ``"phone"`` or ``"unknown"``. None: unknown (the projective model).
        points1_sigma, points2_sigma: each landmark tap's precision in that photo: (N,)
            sigmas in px, or (N, 2, 2) covariances in px^2.
        epipole1_sigma, epipole2_sigma: the precision of a friend's mark: a sigma in px or
            a (2, 2) covariance; for ``epipolar_line1``, the line's sigma across it.
        fundamental_covariance: also return F's first-order covariance
            (``SolveResult.fundamental_covariance``), from which ``shared_solver.matching``
            draws a landmark's band in the other photo; off by default (it costs a few
            tens of microseconds, and 81 numbers of JSON).
        gravity1, gravity2: (3,) which way is down in photo 1's and photo 2's camera frame
            at the shutter (x right along the rows, y down the columns, z out of the lens;
            any length): a phone held upright and level reads (0, 1, 0). Used with a camera
            model, friend 2 marked as a point in photo 1 alone, and both readings given:
            then no landmark gives the level friend 1 is on (``curve2``) and one landmark a
            point. None: everything is as without them.
        gravity_sigma_deg: a reading's standard deviation per axis, degrees, for each
            reading whose own is not given (``gravity1_sigma_deg``, ``gravity2_sigma_deg``).
        heading1, heading2: the compass heading of each phone's lens at the shutter, degrees
            clockwise from north (of the lens axis's horizontal direction; any north both
            phones share). Used where both gravity readings are and both headings given:
            they measure the turn about the vertical, so no landmark gives a stretch of the
            level (``curve2_stretch``, a hint) and landmarks a sharper point. Where the
            landmarks contradict them they are left out (warning ``heading_disagrees``).
        heading_sigma_deg: a heading's standard deviation, degrees, for each heading whose
            own is not given (``heading1_sigma_deg``, ``heading2_sigma_deg``); 15 by
            default, as steel and speakers bend compasses.

    Returns:
        A :class:`SolveResult`; ``model_dump(mode="json")`` is the REST API's JSON.

    Raises:
        SolverError: invalid or degenerate input, with a stable ``code``.
    """
    request = _parse(
        points1,
        points2,
        epipole1=epipole1,
        epipole2=epipole2,
        epipolar_line1=epipolar_line1,
        tap_sigma=tap_sigma,
        image_size1=image_size1,
        image_size2=image_size2,
        landmark_ids=landmark_ids,
        cameras=(camera1, camera2),
        sigmas=(points1_sigma, points2_sigma, epipole1_sigma, epipole2_sigma),
        with_fundamental_covariance=fundamental_covariance,
        gravity=(gravity1, gravity2, gravity_sigma_deg, gravity1_sigma_deg, gravity2_sigma_deg),
        heading=(heading1, heading2, heading_sigma_deg, heading1_sigma_deg, heading2_sigma_deg),
    )
    return _answer(request)


def _answer(request: Request) -> SolveResult:
    """The answer to a checked request: the route its taps and cameras call for."""
    taps = request.taps
    count = len(taps)
    if taps.gravity is not None and request.priors is not None and taps.epipole2 is None:
        return _levelled(request)
    if taps.epipole1 is not None:
        pinhole_route, projective_route, minimum = (
            (pinhole.friend2_marked, projective.both_epipoles, 3)
            if taps.epipole2 is not None
            else (pinhole.friend2_marked, _friend2_projective, 4)
        )
    elif taps.line1 is not None:
        pinhole_route, projective_route, minimum = (
            pinhole.line_through_friend2,
            projective.line_through_friend2,
            6,
        )
    else:
        pinhole_route, projective_route, minimum = (
            pinhole.landmarks_only,
            projective.landmarks_only,
            7,
        )
    if request.priors is None:
        return projective_route(request)
    answer = pinhole_route(request)
    if answer.result is not None and answer.agrees:
        return answer.result
    if count < minimum:
        raise SolverError(Reason.GEOMETRY_UNDETERMINED)
    return disagreement.reconcile(request, answer.result, projective_route(request))


def _levelled(request: Request) -> SolveResult:
    """Friend 2 marked in photo 1, both phones' gravity and a camera model: the level friend 1
    is on from no landmark, else the camera model's fit with gravity in it. Where the fit
    contradicts the readings and the landmarks answer alone, they do, and say so."""
    if not len(request.taps):
        return level.on_the_level(request)
    answer = pinhole.friend2_marked(request)
    if request.taps.heading is not None and not answer.heading_agrees:
        return _told(_levelled(request.without_heading()), WarningCode.HEADING_DISAGREES)
    if answer.result is not None and answer.agrees:
        return answer.result
    without = request.without_gravity()
    if len(without.taps) < fewest_landmarks(epipole1=True, cameras=True):
        raise SolverError(Reason.GEOMETRY_UNDETERMINED)
    return _told(_answer(without), WarningCode.GRAVITY_DISAGREES)


def _told(answer: SolveResult, code: WarningCode) -> SolveResult:
    """The answer with the warning ``code`` first: why it left a sensor out."""
    return answer.model_copy(update={"warnings": [SolverWarning.of(code), *answer.warnings]})


def _friend2_projective(request: Request) -> SolveResult:
    if len(request.taps) == 4:
        return projective.conic(request)
    return projective.friend2_marked(request)


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
    cameras: tuple[CameraInput, CameraInput],
    sigmas: tuple[ArrayLike | None, ArrayLike | None, ArrayLike | None, ArrayLike | None],
    with_fundamental_covariance: bool = False,
    gravity: tuple[ArrayLike | None, ArrayLike | None, float, float | None, float | None] = (
        None,
        None,
        1.0,
        None,
        None,
    ),
    heading: tuple[float | None, float | None, float, float | None, float | None] = (
        None,
        None,
        15.0,
        None,
        None,
    ),
) -> Request:
    sigma = validation.length(tap_sigma, "tap_sigma")
    e1 = None if epipole1 is None else validation.pixel(epipole1, "epipole1")
    e2 = None if epipole2 is None else validation.pixel(epipole2, "epipole2")
    line1 = None if epipolar_line1 is None else validation.line(epipolar_line1, "epipolar_line1")
    if e1 is not None and line1 is not None:
        raise SolverError(Reason.CONFLICTING_INPUTS)
    if e2 is not None and e1 is None:
        raise SolverError(Reason.MISSING_EPIPOLE1)
    size1 = validation.image_size(image_size1, "image_size1")
    size2 = validation.image_size(image_size2, "image_size2")
    camera_pair = (_camera(cameras[0], "camera1", size1), _camera(cameras[1], "camera2", size2))
    modelled = all(camera.kind != "unknown" for camera in camera_pair)
    down = _gravity(*gravity)
    compass = _heading(*heading)
    levelled = down is not None and modelled and e1 is not None and e2 is None
    minimum, marked = _minimum(
        e1 is not None, e2 is not None, line1 is not None, modelled, levelled
    )
    labels = None if landmark_ids is None else [int(i) for i in landmark_ids]
    p, q = validation.landmark_pairs(
        points1,
        points2,
        minimum=minimum,
        marked=marked,
        tolerance=_SAME_PLACE_SIGMAS * sigma,
        labels=labels,
        epipole1=None if e1 is None else homogeneous(e1[None])[0],
        epipole2=None if e2 is None else homogeneous(e2[None])[0],
        directions=not (modelled and e2 is not None) and not levelled,
    )
    if labels is not None and len(labels) != len(p):
        raise SolverError(Reason.ONE_ID_PER_LANDMARK)
    sigma_p, sigma_q, sigma_e1, sigma_e2 = sigmas
    cov_e1 = validation.covariance(sigma_e1, sigma, "epipole1_sigma")
    line_normal = None if line1 is None else line1[:2] / np.hypot(line1[0], line1[1])
    taps = Taps(
        p,
        q,
        validation.covariances(sigma_p, len(p), sigma, "points1_sigma"),
        validation.covariances(sigma_q, len(q), sigma, "points2_sigma"),
        epipole1=e1,
        cov_e1=None if e1 is None else cov_e1,
        epipole2=e2,
        cov_e2=None if e2 is None else validation.covariance(sigma_e2, sigma, "epipole2_sigma"),
        line1=line1,
        line_sigma=1.0
        if line_normal is None
        else float(np.sqrt(line_normal @ cov_e1 @ line_normal)),
        gravity=down,
        heading=compass if down is not None else None,
    )
    return Request(
        taps,
        size1,
        size2,
        labels or list(range(1, len(p) + 1)),
        camera_pair,
        bool(with_fundamental_covariance),
    )


def fewest_landmarks(
    *,
    epipole1: bool,
    epipole2: bool = False,
    line: bool = False,
    cameras: bool,
    position: bool = True,
    gravity: bool = False,
) -> int:
    """How many landmarks (common to both photos) ``solve`` needs.

    Args:
        epipole1: the friend is marked as a point in photo 1; epipole2: in photo 2 too.
        line: a line through the friend is drawn in photo 1 instead.
        cameras: both photos' cameras have a model (``camera1``, ``camera2`` not unknown).
        position: for a position; False: for any answer (four landmarks and the friend
            mark already give the curve the friend is on, without a camera model).
        gravity: both phones' gravity was measured at the shutter.
    """
    if epipole1 and epipole2:
        return 1 if cameras else 3
    if epipole1 and cameras and gravity:
        return 1 if position else 0
    if epipole1:
        return 3 if cameras else (5 if position else 4)
    return 6 if line else 7


def _minimum(
    friend2: bool, friend1: bool, line: bool, modelled: bool, levelled: bool
) -> tuple[int, Marks]:
    """Fewest landmarks for any answer, and how the friends were marked (which the refusal of
    fewer says)."""
    marks = {"epipole1": friend2, "epipole2": friend1, "line": line}
    count = fewest_landmarks(**marks, cameras=modelled, position=False, gravity=levelled)
    if friend2:
        return count, "both" if friend1 else "point"
    return count, "line" if line else "none"


def _gravity(
    gravity1: ArrayLike | None,
    gravity2: ArrayLike | None,
    sigma_deg: float,
    sigma1_deg: float | None,
    sigma2_deg: float | None,
) -> Gravity | None:
    """Both phones' gravity readings, checked; None unless both were given (one reading alone
    says nothing about how the two phones are turned)."""
    default = validation.angle(sigma_deg, "gravity_sigma_deg")
    sigma1 = default if sigma1_deg is None else validation.angle(sigma1_deg, "gravity1_sigma_deg")
    sigma2 = default if sigma2_deg is None else validation.angle(sigma2_deg, "gravity2_sigma_deg")
    down1 = None if gravity1 is None else validation.direction(gravity1, "gravity1")
    down2 = None if gravity2 is None else validation.direction(gravity2, "gravity2")
    if down1 is None or down2 is None:
        return None
    return Gravity(down1, down2, math.radians(sigma1), math.radians(sigma2))


def _heading(
    heading1: float | None,
    heading2: float | None,
    sigma_deg: float,
    sigma1_deg: float | None,
    sigma2_deg: float | None,
) -> Heading | None:
    """Both phones' compass headings, checked; None unless both were given (one heading
    alone says nothing about how the two phones are turned)."""
    largest = validation.LARGEST_HEADING_DEG
    default = validation.angle(sigma_deg, "heading_sigma_deg", largest)
    sigma1 = (
        default
        if sigma1_deg is None
        else validation.angle(sigma1_deg, "heading1_sigma_deg", largest)
    )
    sigma2 = (
        default
        if sigma2_deg is None
        else validation.angle(sigma2_deg, "heading2_sigma_deg", largest)
    )
    first = None if heading1 is None else validation.heading(heading1, "heading1")
    second = None if heading2 is None else validation.heading(heading2, "heading2")
    if first is None or second is None:
        return None
    return Heading(first, second, math.radians(sigma1), math.radians(sigma2))


def _camera(value: CameraInput, name: str, size: tuple[float, float] | None) -> Camera:
    """A camera description from any of its accepted forms, refused when malformed."""
    parse: Callable[[], Camera]
    if value is None:
        return _UNKNOWN
    if isinstance(value, Camera):
        camera = value
    elif isinstance(value, str) and value in _BY_KIND:
        camera = _BY_KIND[value]
    else:
        if isinstance(value, str):
            parse = lambda: Camera.model_validate({"kind": value})  # noqa: E731
        else:
            parse = lambda: Camera.model_validate(value)  # noqa: E731
        try:
            camera = parse()
        except ValidationError as error:
            reason = error.errors()[0].get("msg", "not a camera")
            raise SolverError(Reason.NOT_A_CAMERA, field=name, detail=reason) from error
    if camera.kind != "unknown" and size is None:
        size_name = "image_size1" if name == "camera1" else "image_size2"
        raise SolverError(Reason.CAMERA_WITHOUT_SIZE, field=size_name)
    return camera
