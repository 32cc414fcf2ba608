"""No landmark, friend 2 marked in photo 1, both phones' gravity: the level friend 1 is on.

Gravity in both photos fixes how the two phones are tilted against each other; friend 2's
mark fixes the direction between them in photo 1. One unknown is left, the turn about the
vertical (:mod:`..minimal.gravity_and_one`). Whatever the turn, friend 1 is seen from
friend 2 at the angle from down that friend 2 is seen from friend 1, mirrored:
``g2 . v2 = -g1 . b1`` for friend 1's direction ``v2`` (frame 2) and friend 2's ``b1``
(frame 1). In photo 2 that cone is a curve: one level of the stands. It is drawn at the
priors' focal lengths, the only ones known without a landmark.

Its 95 % half-width is first order in every input: both readings (each ``sigma`` per
axis), friend 2's mark (its covariance) and both focal lengths (their priors' log sigmas),
each moving ``s = g2 . u2 - c``, the cosine offset of a pixel's ray ``u2`` from the cone
(``c = -g1 . b1``), divided by how fast ``s`` changes across the curve in px.

Both phones' compass headings, when given, measure the turn
(:func:`..minimal.gravity_and_one.turn_from_headings`): the stretch of the curve within
their 95 % range of turns is where they point (``curve2_stretch``). It stays a hint: no
landmark checks the compasses, which steel bends by tens of degrees.
"""

from __future__ import annotations

import math

import numpy as np

from ..drawing.curves import simplified
from ..errors import Reason, WarningCode
from ..estimation.camera import FocalPrior, focal_35mm
from ..estimation.taps import Gravity
from ..minimal.gravity_and_one import level_frame, turn_from_headings
from ..projective import Array, Mask, inside
from ..refusal import SolverError
from ..result import CameraEstimate, SolveResult, SolverWarning
from .building import pixel, unit
from .request import Request

# 95 % of a one-dimensional normal lies within this many sigmas: the band across the curve.
_BAND_SIGMAS = 1.959963984540054
# The curve is first found at this many turns about the vertical, then resampled where it
# crosses the photo so that its points are at most _STEP_PX apart (a chord of 4 px strays
# 0.04 px from a curve of radius 50 px), then simplified as the other curves are
# (drawing.curves.simplified). Its half-width is read at up to _WIDTHS_READ of those points.
_COARSE = 1024
_STEP_PX = 4.0
_WIDTHS_READ = 128
# Friend 1 within this angle (radians) of straight up or down from friend 2 is on no level:
# the cone closes to a line and the curve to a point.
_STRAIGHT_ABOVE = 1e-3


def on_the_level(request: Request) -> SolveResult:
    """The curve in photo 2 on which friend 1 stands, ``curve2``, and its 95 % half-width.

    Raises:
        SolverError: friend 2 straight above or below friend 1 (``friend_undetermined``).
    """
    taps, priors, gravity = request.taps, request.priors, request.taps.gravity
    size1, size2 = request.size1, request.size2
    assert taps.epipole1 is not None
    assert taps.cov_e1 is not None
    assert gravity is not None
    assert priors is not None
    assert size1 is not None
    assert size2 is not None
    ray1 = _ray(taps.epipole1, priors[0])
    b1 = ray1 / float(np.linalg.norm(ray1))
    cosine = -float(gravity.gravity1 @ b1)
    if abs(cosine) > math.cos(_STRAIGHT_ABOVE):
        raise SolverError(Reason.FRIEND_UNDETERMINED)
    pieces = _visible(_directions(gravity, b1), priors[1], size2)
    visible = np.concatenate(pieces) if pieces else np.zeros((0, 2))
    read = visible[:: max(1, math.ceil(len(visible) / _WIDTHS_READ))]
    widths = _halfwidths(read, gravity, ray1, taps.cov_e1, priors)
    halfwidth = float(np.median(widths)) if len(widths) else None
    stretch = None
    if taps.heading is not None:
        stretch = [simplified(piece) for piece in _stretch(request, b1)] or None
    return SolveResult(
        method="pinhole_level",
        camera_model="pinhole",
        cameras=[
            CameraEstimate(
                known=camera.kind,
                focal_px=prior.focal_px,
                focal_35mm=focal_35mm(prior.focal_px, size),
                focal_35mm_sd=None,
            )
            for camera, prior, size in zip(request.cameras, priors, (size1, size2), strict=True)
        ],
        landmark_count=0,
        tap_sigma=request.sigma,
        epipole2=None,
        epipole2_h=None,
        epipole1=pixel(np.append(taps.epipole1, 1.0)),
        epipole1_h=unit(np.append(taps.epipole1, 1.0)),
        curve2=[simplified(piece) for piece in pieces],
        curve2_halfwidth=halfwidth,
        curve2_stretch=stretch,
        used_gravity=True,
        used_heading=taps.heading is not None,
        quality="fair",
        warnings=[SolverWarning.of(WarningCode.ON_THE_LEVEL)],
    )


def _stretch(request: Request, b1: Array) -> list[Array]:
    """The pieces (M, 2) px of the curve inside photo 2 within the headings' 95 % range of
    turns about the vertical, at most ``_STEP_PX`` apart."""
    taps, priors, size2 = request.taps, request.priors, request.size2
    gravity, heading = taps.gravity, taps.heading
    assert gravity is not None
    assert heading is not None
    assert priors is not None
    assert size2 is not None
    circle = _directions(gravity, b1)
    # The circle's parameter is the turn plus friend 2's azimuth in photo 1's level frame
    # (_directions: v(a) = -Q2^T Rz(psi) Q1 b1, a = psi + that azimuth).
    levelled = level_frame(gravity.gravity1) @ b1
    centre = turn_from_headings(
        gravity.gravity1, gravity.gravity2, heading.heading1, heading.heading2
    ) + math.atan2(levelled[1], levelled[0])
    half = min(_BAND_SIGMAS * heading.sigma, math.pi)
    return _visible(circle, priors[1], size2, (centre - half, centre + half))


def _ray(point: Array, prior: FocalPrior) -> Array:
    """(3,) the ray ``K^-1 (x, y, 1)`` of a pixel at the prior's focal length."""
    (cx, cy), focal = prior.centre, prior.focal_px
    return np.array([(point[0] - cx) / focal, (point[1] - cy) / focal, 1.0])


def _directions(gravity: Gravity, b1: Array) -> Array:
    """A function of the turn: friend 1's unit directions (K, 3) in frame 2 for turns (K,).

    Returned as the two fixed vectors of ``v(a) = -Q2^T (h cos a, h sin a, z)``: the
    circle's centre and its two axes, rows of a (3, 3)."""
    levelled = level_frame(gravity.gravity1) @ b1  # friend 2's direction, z along down
    height = math.hypot(levelled[0], levelled[1])
    back = level_frame(gravity.gravity2).T
    return np.array([-back[:, 2] * levelled[2], -back[:, 0] * height, -back[:, 1] * height])


def _at(circle: Array, turns: Array) -> Array:
    """(K, 3) friend 1's directions at the turns (K,) of :func:`_directions`' circle."""
    result: Array = (
        circle[0] + np.cos(turns)[:, None] * circle[1] + np.sin(turns)[:, None] * circle[2]
    )
    return result


def _project(directions: Array, prior: FocalPrior) -> Array:
    """(K, 2) pixels of directions in front of the camera (NaN behind or beside it)."""
    (cx, cy), focal = prior.centre, prior.focal_px
    with np.errstate(divide="ignore", invalid="ignore"):
        depth = np.where(directions[:, 2] > 1e-9, directions[:, 2], np.nan)
        return np.stack(
            [cx + focal * directions[:, 0] / depth, cy + focal * directions[:, 1] / depth],
            axis=1,
        )


def _visible(
    circle: Array,
    prior: FocalPrior,
    size: tuple[float, float],
    between: tuple[float, float] | None = None,
) -> list[Array]:
    """The curve's stretches inside the photo, (M, 2) px each, at most ``_STEP_PX`` apart;
    only those of turns ``between`` (low, high) of :func:`_directions`' circle when given."""
    if between is None:
        # Start behind the camera (the turn of least depth): no visible stretch cut in two.
        behind = math.atan2(circle[2, 2], circle[1, 2]) + math.pi
        between = (behind, behind + 2.0 * math.pi)
    # As finely as the whole circle is first sampled, over whatever part of it is asked.
    coarse_count = max(math.ceil(_COARSE * (between[1] - between[0]) / (2.0 * math.pi)), 8)
    turns = np.linspace(*between, coarse_count + 1)
    seen = inside(_project(_at(circle, turns), prior), size)
    pieces = []
    step = turns[1] - turns[0]
    for start, stop in _runs(seen):
        # From the turn before the run to the one after, resampled finely enough.
        low, high = turns[max(start - 1, 0)], turns[min(stop, coarse_count)]
        coarse = _project(_at(circle, np.linspace(low, high, stop - start + 2)), prior)
        finite = coarse[np.isfinite(coarse).all(axis=1)]
        longest = float(np.max(np.hypot(*np.diff(finite, axis=0).T), initial=0.0))
        count = max(math.ceil(longest / _STEP_PX * (high - low) / step), 2) + 1
        fine = _project(_at(circle, np.linspace(low, high, count)), prior)
        for a, b in _runs(inside(fine, size)):
            if b - a >= 2:
                pieces.append(fine[a:b])
    return pieces


def _runs(flags: Mask) -> list[tuple[int, int]]:
    """``[start, stop)`` of each run of True."""
    edges = np.diff(np.concatenate([[0], flags.astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edges == 1).tolist(), np.flatnonzero(edges == -1).tolist()
    return list(zip(starts, stops, strict=True))


def _halfwidths(
    points: Array,
    gravity: Gravity,
    ray1: Array,
    cov_e1: Array,
    priors: tuple[FocalPrior, FocalPrior],
) -> Array:
    """(M,) the band's 95 % half-width across the curve at its points (M, 2), px.

    ``ray1``: (3,) friend 2's ray ``K1^-1 e1``; ``cov_e1``: (2, 2) its mark's covariance."""
    g1, g2 = gravity.gravity1, gravity.gravity2
    b1 = ray1 / float(np.linalg.norm(ray1))
    (cx, cy), f2 = priors[1].centre, priors[1].focal_px
    rays2 = np.column_stack(
        [(points[:, 0] - cx) / f2, (points[:, 1] - cy) / f2, np.ones(len(points))]
    )
    norms2 = np.linalg.norm(rays2, axis=1)
    u2 = rays2 / norms2[:, None]
    # Each reading moves the cone by sigma per axis across down: sin of its angle to b1, u2.
    variance = gravity.sigma1**2 * (1.0 - float(g1 @ b1) ** 2) + gravity.sigma2**2 * (
        1.0 - (u2 @ g2) ** 2
    )
    # Friend 2's mark and photo 1's focal length move b1: d b1 = (I - b1 b1^T) d ray1 / |ray1|.
    across1 = (g1 - float(g1 @ b1) * b1) / float(np.linalg.norm(ray1))
    along_mark = across1[:2] / priors[0].focal_px
    variance = variance + float(along_mark @ cov_e1 @ along_mark)
    variance = variance + (priors[0].log_sigma * float(across1[:2] @ ray1[:2])) ** 2
    # Photo 2's focal length moves every pixel's ray; how fast s changes across the curve.
    across2 = (g2[None, :] - (u2 @ g2)[:, None] * u2) / norms2[:, None]  # (M, 3)
    moved = np.einsum("mi,mi->m", across2[:, :2], rays2[:, :2])
    variance = variance + (priors[1].log_sigma * moved) ** 2
    slope = np.linalg.norm(across2[:, :2], axis=1) / priors[1].focal_px
    result: Array = _BAND_SIGMAS * np.sqrt(variance) / slope
    return result
