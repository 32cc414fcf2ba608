"""From a fitted model to the :class:`..result.SolveResult` a person reads.

Every route ends here: friend 1's oriented position, the 95 % region (as fitted, calibrated
or widened), the residuals, the quality grade and the sentences that go with them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import cast

import numpy as np

from .. import linalg, words
from ..errors import WarningCode
from ..estimation import bootstrap
from ..estimation.camera import focal_35mm
from ..estimation.epipolar_fit import EpipolarFit, sampson_distances
from ..estimation.pinhole.fit import PinholeFit
from ..estimation.planar import PlanarFit
from ..estimation.plausibility import Plausibility, assess, orient_epipole2
from ..estimation.uncertainty import Fitted, consistent, ellipse, holdable, quality
from ..projective import (
    Array,
    canonical,
    canonical_matrix,
    far_pixel,
    homogeneous,
    skew,
    to_pixel,
)
from ..result import (
    CameraEstimate,
    CameraModel,
    Candidate,
    Covariance9,
    Ellipse,
    Matrix,
    Method,
    SolveResult,
    SolverWarning,
    Uncertainty,
)
from .request import Request

Geometry = tuple[Array, Array, Array]  # (e1, e2, F)


@dataclass(frozen=True)
class Answer:
    """What a fitted model says, before it becomes a :class:`SolveResult`."""

    epipole1: Array  # (3,) friend 2 in photo 1
    epipole2: Array  # (3,) friend 1 in photo 2; any sign unless ``oriented``
    covariance: Array | None  # (2, 2) px^2 of epipole2, None: no region claimed
    residuals: Array  # (N,) px
    fundamental: Array  # (3, 3); for the plane model the one it induces, [e2]x H
    homography: Array | None = None
    oriented: bool = False  # the signs of both epipoles come from the model itself
    orientable: bool = True  # ... and every landmark is in front of both cameras
    camera_model: CameraModel = "projective"
    cameras: tuple[CameraEstimate, ...] = ()
    conic: Array | None = None  # (3, 3) the curve of four landmarks, drawn alongside
    fundamental_covariance: Array | None = None  # (9, 9), row by row, widened with e2's

    @classmethod
    def of_fit(cls, request: Request, fit: EpipolarFit, covariance: Array | None) -> Answer:
        return cls._of_fundamental(request, fit, covariance, cameras=unknown_cameras(request))

    @classmethod
    def of_plane(cls, request: Request, plane: PlanarFit) -> Answer:
        taps = request.taps
        assert taps.epipole1 is not None
        assert taps.cov_e1 is not None
        friend1, covariance = plane.friend1(taps.epipole1, taps.cov_e1)
        mapped = homogeneous(taps.p) @ plane.homography.T
        transfer = np.linalg.norm(mapped[:, :2] / mapped[:, 2:] - taps.q, axis=1)
        induced = skew(friend1) @ plane.homography
        return cls(
            np.append(taps.epipole1, 1.0),
            friend1,
            covariance,
            transfer,
            induced,
            plane.homography,
            cameras=unknown_cameras(request),
        )

    @classmethod
    def of_pinhole(
        cls, request: Request, fit: PinholeFit, covariance: Array | None, *, orientable: bool
    ) -> Answer:
        return cls._of_fundamental(
            request,
            fit,
            covariance,
            cameras=pinhole_cameras(request, fit),
            oriented=True,
            orientable=orientable,
            camera_model="pinhole",
        )

    @classmethod
    def _of_fundamental(
        cls,
        request: Request,
        fit: EpipolarFit | PinholeFit,
        covariance: Array | None,
        *,
        cameras: tuple[CameraEstimate, ...],
        oriented: bool = False,
        orientable: bool = True,
        camera_model: CameraModel = "projective",
    ) -> Answer:
        """A fitted fundamental matrix's answer (the general and the pinhole model alike):
        the taps' Sampson distances as residuals, F's covariance widened when asked."""
        distances = np.abs(sampson_distances(fit.fundamental, request.taps.p, request.taps.q))
        return cls(
            fit.epipole1,
            fit.epipole2,
            covariance,
            distances,
            fit.fundamental,
            oriented=oriented,
            orientable=orientable,
            camera_model=camera_model,
            cameras=cameras,
            fundamental_covariance=_widened(fit, fit.fundamental_covariance)
            if request.with_fundamental_covariance
            else None,
        )


def unknown_cameras(request: Request) -> tuple[CameraEstimate, ...]:
    """The cameras as given, with no focal length: the projective model has none."""
    if all(camera.kind == "unknown" for camera in request.cameras):
        return ()
    return tuple(
        CameraEstimate(known=camera.kind, focal_px=None, focal_35mm=None, focal_35mm_sd=None)
        for camera in request.cameras
    )


def pinhole_cameras(request: Request, fit: PinholeFit) -> tuple[CameraEstimate, ...]:
    """Both cameras' fitted focal lengths, in px and as 35 mm equivalents with their sd."""
    sizes = (request.size1, request.size2)
    estimates = []
    for index, (camera, focal, size) in enumerate(
        zip(request.cameras, fit.focals, sizes, strict=True)
    ):
        assert size is not None
        sd = focal * math.sqrt(max(float(fit.covariance[5 + index, 5 + index]), 0.0))
        estimates.append(
            CameraEstimate(
                known=camera.kind,
                focal_px=focal,
                focal_35mm=focal_35mm(focal, size),
                focal_35mm_sd=focal_35mm(sd, size),
            )
        )
    return tuple(estimates)


def result(
    method: Method,
    request: Request,
    answer: Answer,
    *,
    suspects: list[int],
    warnings: list[SolverWarning],
    inconsistent: bool = False,
    candidates: list[Candidate] | None = None,
) -> SolveResult:
    """The answer as the person reads it: oriented position, region, grade, sentences."""
    taps = request.taps
    e1 = canonical(answer.epipole1)
    if answer.oriented:
        e2, orientable = answer.epipole2, answer.orientable
    else:
        # Friend 2 is seen in photo 1, so in front of friend 1's camera: that orients e1,
        # and through the landmarks e2 (in front of friend 2's camera, behind it, or
        # sideways).
        e2, orientable = orient_epipole2(answer.fundamental, e1, answer.epipole2, taps.p, taps.q)
    position = pixel(e2)
    uncertainty, semi_major = _uncertainty(position, answer.covariance)
    region = quality(semi_major, request.diagonal2)
    behind_you = "no"
    if position is not None and e2[2] < 0:
        # Behind friend 2: nothing to mark in the photo. Only a pinned-down, physical answer
        # may say "behind you": a loose one may have crossed infinity, and a fit that breaks
        # the oriented constraint has no reliable side (both measured on 5-landmark taps).
        behind_you = "yes" if orientable and region != "poor" else "unsure"
        position, uncertainty = None, Uncertainty(ellipse=None)
    grade = region
    if inconsistent or (position is None and behind_you != "yes"):
        grade = "poor"
    return SolveResult(
        method=method,
        camera_model=answer.camera_model,
        cameras=list(answer.cameras),
        landmark_count=len(taps),
        tap_sigma=request.sigma,
        epipole2=position,
        epipole2_h=unit(e2),
        epipole1=pixel(e1),
        epipole1_h=unit(e1),
        fundamental=None if answer.homography is not None else matrix(answer.fundamental),
        # One of several geometries (candidates) has no uncertainty of its own to claim.
        fundamental_covariance=None
        if answer.homography is not None or candidates or answer.fundamental_covariance is None
        else covariance9(answer.fundamental_covariance),
        homography=None if answer.homography is None else matrix(answer.homography),
        conic2=None if answer.conic is None else matrix(answer.conic),
        candidates=candidates or [],
        uncertainty=uncertainty,
        suspect_landmarks=suspects,
        residuals=[float(r) for r in answer.residuals],
        quality=grade,
        used_gravity=taps.gravity is not None and answer.camera_model == "pinhole",
        used_heading=taps.heading is not None
        and taps.gravity is not None
        and answer.camera_model == "pinhole",
        warnings=warnings
        + where_warnings(
            request, e2, behind=behind_you, loose=semi_major is not None and region == "poor"
        ),
    )


def candidates(
    request: Request, geometries: list[Geometry], cues: list[Plausibility]
) -> list[Candidate]:
    """Every geometry that fits, in rank order, with the cues that ranked it (one each)."""
    taps = request.taps
    listed = []
    for rank, ((friend2, friend1, f), cue) in enumerate(zip(geometries, cues, strict=True), 1):
        e1 = canonical(friend2)
        e2, _ = orient_epipole2(f, e1, friend1, taps.p, taps.q)
        listed.append(
            Candidate(
                rank=rank,
                epipole1=pixel(e1),
                epipole1_h=unit(e1),
                epipole2=pixel(e2),
                epipole2_h=unit(e2),
                fundamental=matrix(canonical_matrix(f)),
                oriented_violations=cue.oriented_violations,
                focal_lengths=cue.focal_lengths,
                phone_like=cue.phone_like,
            )
        )
    return listed


def pinhole_candidates(request: Request, fits: list[PinholeFit]) -> list[Candidate]:
    """Every pose that fits about as well, best first, oriented by the model itself."""
    taps = request.taps
    listed = []
    for rank, fit in enumerate(fits, 1):
        cue = assess(
            fit.fundamental,
            fit.epipole1,
            fit.epipole2,
            taps.p,
            taps.q,
            image_size1=request.size1,
            image_size2=request.size2,
        )
        listed.append(
            Candidate(
                rank=rank,
                epipole1=pixel(fit.epipole1),
                epipole1_h=unit(fit.epipole1),
                epipole2=pixel(fit.epipole2) if fit.epipole2[2] > 0 else None,
                epipole2_h=unit(fit.epipole2),
                fundamental=matrix(canonical_matrix(fit.fundamental)),
                oriented_violations=cue.oriented_violations,
                focal_lengths=fit.focals,
                phone_like=cue.phone_like,
            )
        )
    return listed


# --- consistency and warnings -----------------------------------------------------------


def widen_if_inconsistent(
    fit: Fitted, covariance: Array | None, warnings: list[SolverWarning]
) -> tuple[Array | None, bool]:
    """Taps noisier than their precisions say (and no culprit found): widen the ellipse by
    the reduced chi-square and add a warning.

    Returns the covariance to report and whether the taps were inconsistent.
    """
    if consistent(fit):
        return covariance, False
    warnings.append(SolverWarning.of(WarningCode.MARKS_DISAGREE))
    return _widened(fit, covariance), True


def _widened(fit: Fitted, covariance: Array | None) -> Array | None:
    """The covariance of a fit whose taps are noisier than their precisions say grown by
    the reduced chi-square; as it is otherwise."""
    if covariance is None or consistent(fit):
        return covariance
    return covariance * (fit.cost / fit.dof)


def calibrated(
    answer: Array, covariance: Array | None, samples: Callable[[], Array]
) -> Array | None:
    """The covariance grown until its ellipse holds the bootstrap's answers (see bootstrap);
    None when too many of them have no position for any ellipse to hold them.

    Args:
        answer: (3,) the homogeneous position of friend 1 that the covariance belongs to.
    """
    position = far_pixel(answer)  # however far: the bootstrap's answers are, too
    if covariance is None or position is None:
        return covariance
    factor = bootstrap.scale(position, covariance, samples())
    # Re-made taps too often give no position at all: no region would hold the truth.
    return covariance * factor if math.isfinite(factor) else None


def suspect_warnings(
    request: Request, suspects: list[int], fundamental: Array
) -> list[SolverWarning]:
    off = np.abs(sampson_distances(fundamental, request.taps.p, request.taps.q))
    return [
        SolverWarning.of(
            WarningCode.MISTAPPED, landmark=request.labels[i], distance_px=float(off[i])
        )
        for i in suspects
    ]


def where_warnings(request: Request, e2: Array, *, behind: str, loose: bool) -> list[SolverWarning]:
    """Warnings about where friend 1 is relative to friend 2's photo (oriented e2).

    ``behind``: "no", "yes" (pinned down behind friend 2's camera) or "unsure"; ``loose``:
    the 95 % region is wider than a tenth of the photo.
    """
    warnings = []
    position = to_pixel(e2)
    if position is None:
        warnings.append(SolverWarning.of(WarningCode.FAR_TO_THE_SIDE))
    elif behind != "no":
        code = WarningCode.NOT_PINNED_DOWN if behind == "unsure" else WarningCode.BEHIND_YOU
        return [SolverWarning.of(code)]
    elif request.size2 is not None:
        width, height = request.size2
        x, y = position
        beyond = max(-x, x - width, -y, y - height)
        if beyond > 0:
            side: words.Side = (
                ("left" if x < 0 else "right")
                if max(-x, x - width) >= max(-y, y - height)
                else ("up" if y < 0 else "down")
            )
            warnings.append(
                SolverWarning.of(WarningCode.OUTSIDE_PHOTO, distance_px=float(beyond), side=side)
            )
    if loose:
        warnings.append(SolverWarning.of(WarningCode.UNCERTAIN))
    return warnings


# --- small conversions ------------------------------------------------------------------


def _uncertainty(
    e2: tuple[float, float] | None, covariance: Array | None
) -> tuple[Uncertainty, float | None]:
    if e2 is None or covariance is None or not np.isfinite(covariance).all():
        return Uncertainty(ellipse=None), None
    # A covariance inverted from nearly singular normal equations (taps far outside a photo
    # seen through a camera model, ~90 degrees off its axis) can come out lopsided or
    # indefinite: a region with a zero axis would be a false certainty, so there is none.
    covariance = (covariance + covariance.T) / 2.0
    (a, b), (c, d) = covariance.tolist()
    if not (a > 0.0 and a * d - b * c > 0.0):  # positive definite (numpy's det: 10x the time)
        return Uncertainty(ellipse=None), None
    centre, axes, angle = ellipse(np.array(e2), covariance)
    if not holdable(axes):
        return Uncertainty(ellipse=None), None
    return Uncertainty(
        ellipse=Ellipse(center=centre, axes=axes, angle_deg=angle), covariance=((a, b), (c, d))
    ), axes[0]


def pixel(point: Array) -> tuple[float, float] | None:
    position = to_pixel(point)
    return None if position is None else (float(position[0]), float(position[1]))


def pixel_or_nan(point: Array) -> Array:
    position = to_pixel(point)
    return np.full(2, np.nan) if position is None else position


def unit(point: Array) -> tuple[float, float, float]:
    """A homogeneous point at unit norm, its sign (orientation) kept."""
    x, y, w = point / linalg.norm(point)
    return float(x), float(y), float(w)


def covariance9(values: Array) -> Covariance9:
    """A (9, 9) array as nested tuples of floats (``tolist`` converts in one call)."""
    return cast(Covariance9, tuple(map(tuple, values.tolist())))


def matrix(values: Array) -> Matrix:
    first, second, third = (_row(row) for row in values)
    return first, second, third


def _row(row: Array) -> tuple[float, float, float]:
    return float(row[0]), float(row[1]), float(row[2])
