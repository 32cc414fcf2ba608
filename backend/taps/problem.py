"""From the two friends' taps to the solver's question, and from its answer back to what
each phone is told: where its friend is in its own photo.

The solver speaks of photo 1 and photo 2 (``epipole1`` in photo 1, ``epipole2`` in photo
2); the friends do not. Photo 1 is the photo of a friend who marked the other: the starter's
if it has a mark, else the joiner's; a point before a line (:class:`PhotoOrder`). Landmarks
are matched by id (#3 in one photo is #3 in the other); only ids tapped in both photos count,
in ascending order. Every photo of a session comes from a phone, so each camera is a
phone's: its lens's 35 mm focal length when the photo told it (``known_focal``), else the
phone prior. The counts come from the solver itself (``fewest_landmarks``).
docs/geometry.md has the geometry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from backend.participants import ROLES, Role
from backend.photos.gravity import Gravity
from backend.photos.heading import Heading
from backend.photos.lens import EXIF_UNCERTAINTY
from shared_solver import (
    Camera,
    SolverError,
    SolveResult,
    SolverWarning,
    WarningCode,
    fewest_landmarks,
    solve,
)
from shared_solver.drawing.layout import answer_drawing
from shared_solver.drawing.shapes import AnswerDrawing

from . import guidance
from .photo_order import PhotoNumber, PhotoOrder
from .schemas import Answer, FriendInPhoto, LandmarkBand, StoredAnswer, Taps

Point = tuple[float, float]
Line = tuple[float, float, float]


@dataclass(frozen=True)
class PhotoFacts:
    """What the solver is told of both photos besides the taps, by role: each one's size
    (width, height px), its camera, and its phone's gravity and compass heading at the
    shutter (None: not read)."""

    sizes: dict[Role, tuple[int, int]]
    cameras: dict[Role, Camera]
    readings: dict[Role, Gravity | None]
    headings: dict[Role, Heading | None] = field(default_factory=dict)

    @property
    def levelled(self) -> bool:
        """Both photos have the phone's gravity."""
        return all(self.readings.get(role) is not None for role in ROLES)


@dataclass(frozen=True)
class Problem:
    """What the solver is asked, in stored-photo pixels; ``order`` says whose photo is
    photo 1."""

    order: PhotoOrder
    default_sigma: float
    ids: list[int]
    points1: list[Point]
    points2: list[Point]
    sigmas1: list[float]
    sigmas2: list[float]
    epipole1: Point | None = None
    epipole1_sigma: float | None = None
    line1: Line | None = None
    epipole2: Point | None = None
    epipole2_sigma: float | None = None
    levelled: bool = False  # both photos have the phone's gravity at the shutter

    def fewest(self, *, position: bool, cameras: bool = True) -> int:
        """Landmarks (common to both photos) the solver needs, phone cameras given (or,
        ``cameras=False``, without the camera model)."""
        return fewest_landmarks(
            epipole1=self.epipole1 is not None,
            epipole2=self.epipole2 is not None,
            line=self.line1 is not None,
            cameras=cameras,
            position=position,
            gravity=self.levelled,
        )

    def landmarks_needed(self, answer: Answer | None = None) -> int:
        """How many more common landmarks until a position. Counted for phone cameras,
        unless the answer so far had to do without the camera model: taps that fit no two
        phone photos are answered as the paper's projective geometry counts (four
        landmarks and a friend mark: the curve, and one more for a position)."""
        projective = answer is not None and answer.camera_model == "projective"
        return max(0, self.fewest(position=True, cameras=not projective) - len(self.ids))

    @property
    def solvable(self) -> bool:
        return len(self.ids) >= self.fewest(position=False)


def problem(
    taps: dict[Role, Taps | None], default_sigma: float, *, levelled: bool = False
) -> Problem:
    """The common landmarks and the friends' marks, with each tap's precision (a tap sent
    without one has ``default_sigma``); ``levelled``: both photos have gravity."""
    sets = {role: taps.get(role) or Taps() for role in ROLES}
    order = _order(sets)
    mine, theirs = sets[order.first], sets[order.second]
    one = {tap.id: tap for tap in mine.landmarks}
    two = {tap.id: tap for tap in theirs.landmarks}
    ids = sorted(one.keys() & two.keys())

    def sigma(value: float | None) -> float:
        return default_sigma if value is None else value

    # mark1: friend 2 as marked in photo 1 (e1); mark2: friend 1 in photo 2 (e2).
    mark1 = mine.friend
    line1 = mine.friend_line if mark1 is None else None
    # The other phone's mark is the solver's epipole2 only beside a point in photo 1.
    mark2 = theirs.friend if mark1 is not None else None
    return Problem(
        order=order,
        default_sigma=default_sigma,
        ids=ids,
        points1=[(one[i].x, one[i].y) for i in ids],
        points2=[(two[i].x, two[i].y) for i in ids],
        sigmas1=[sigma(one[i].sigma) for i in ids],
        sigmas2=[sigma(two[i].sigma) for i in ids],
        epipole1=None if mark1 is None else (mark1.x, mark1.y),
        epipole1_sigma=(
            sigma(mark1.sigma)
            if mark1 is not None
            else sigma(line1.sigma)
            if line1 is not None
            else None
        ),
        line1=None if line1 is None else (line1.a, line1.b, line1.c),
        epipole2=None if mark2 is None else (mark2.x, mark2.y),
        epipole2_sigma=None if mark2 is None else sigma(mark2.sigma),
        levelled=levelled,
    )


def _order(sets: dict[Role, Taps]) -> PhotoOrder:
    """Whose photo is photo 1: a point marked before a line, the starter before the joiner."""
    for mark in ("friend", "friend_line"):
        for role in ROLES:
            if getattr(sets[role], mark) is not None:
                return PhotoOrder(role)
    return PhotoOrder("starter")


@dataclass
class KnownFit:
    """An answer computed before, as stored (a solution or an error), and the
    problem it answered: the solver is deterministic, so the same problem (the same taps,
    photos and cameras) is answered from it instead of solving again. A change of taps
    often leaves the problem as it was (a landmark the other phone has not tapped yet), and
    judging a new landmark against the others asks the problem from before the change."""

    task: Problem
    stored: StoredAnswer
    _result: SolveResult | SolverError | None = None

    def result(self) -> SolveResult:
        """The stored answer as the solver gave it. Raises its SolverError."""
        if self._result is None:
            solution, error = self.stored.solution, self.stored.error
            if solution is not None:
                self._result = SolveResult.model_validate(solution)
            elif error is not None:
                self._result = SolverError(error)
            else:
                raise ValueError("a stored answer with neither a solution nor an error")
        if isinstance(self._result, SolverError):
            raise self._result
        return self._result


def known_fit(
    stored: StoredAnswer | None,
    taps: dict[Role, Taps | None],
    default_sigma: float,
    *,
    levelled: bool = False,
) -> KnownFit | None:
    """``stored``, the answer to these taps (and the photos they were on), as a known fit."""
    if stored is None or (stored.solution is None and stored.error is None):
        return None
    return KnownFit(problem(taps, default_sigma, levelled=levelled), stored)


def camera(focal_35mm: float | None, uncertainty: float | None = None) -> Camera:
    """A phone's camera: its lens's focal length when its photo said, else the phone prior."""
    if focal_35mm is None:
        return Camera.phone()
    return Camera.with_focal(focal_35mm, uncertainty or EXIF_UNCERTAINTY)


def solved(
    task: Problem,
    photos: PhotoFacts,
    *,
    taps: dict[Role, Taps | None],
    misfits: dict[Role, list[int]],
    known: KnownFit | None = None,
) -> StoredAnswer:
    """The solver's answer to ``task`` as stored, or its refusal (its reason and parameters:
    ``backend.taps.shown`` words it for each phone)."""
    sizes = photos.sizes
    try:
        result = fit(task, photos, known=known)
    except SolverError as error:
        return StoredAnswer(error=error.refusal)
    solution = result.model_dump(mode="json")
    guides = guidance.bands(result, task.order, taps, sizes, task.default_sigma)
    told = answer(task, result, sizes, drawn=_known_drawings(task, known))
    for role, view in told.in_photo.items():
        view.bands = [LandmarkBand(id=i, **band.model_dump()) for i, band in guides[role].items()]
        view.misfits = misfits[role]
        # A misfit the fit left out already has its sentence ("looks mis-tapped"): one is enough.
        flagged = [i for i in misfits[role] if i not in told.suspects]
        view.warnings = [
            SolverWarning.of(WarningCode.MISFIT, photo=task.order.number(role), landmark=i)
            for i in flagged
        ] + view.warnings
    return StoredAnswer(answer=told, solution=solution, first=task.order.first)


def fit(task: Problem, photos: PhotoFacts, *, known: KnownFit | None = None) -> SolveResult:
    """The solver's answer to ``task``, with the uncertainty of its geometry (for the bands
    of the landmarks still to find); ``known``'s if it answered the same problem on the
    same photos. The phones' gravity is used when the task is ``levelled``; their compass
    headings when both photos have one (the solver uses them only beside both gravities).
    Raises SolverError."""
    if known is not None and known.task == task:
        return known.result()
    order = task.order
    sizes, cameras, readings = photos.sizes, photos.cameras, photos.readings
    first, second = (
        (readings[order.first], readings[order.second]) if task.levelled else (None, None)
    )
    compass1, compass2 = (photos.headings.get(order.first), photos.headings.get(order.second))
    if compass1 is None or compass2 is None:
        compass1 = compass2 = None
    return solve(
        task.points1,
        task.points2,
        epipole1=task.epipole1,
        epipole2=task.epipole2,
        epipolar_line1=task.line1,
        tap_sigma=task.default_sigma,
        image_size1=sizes[order.first],
        image_size2=sizes[order.second],
        landmark_ids=task.ids,
        camera1=cameras[order.first],
        camera2=cameras[order.second],
        points1_sigma=task.sigmas1 or None,
        points2_sigma=task.sigmas2 or None,
        epipole1_sigma=task.epipole1_sigma,
        epipole2_sigma=task.epipole2_sigma,
        fundamental_covariance=True,
        gravity1=None if first is None else first.down,
        gravity2=None if second is None else second.down,
        gravity1_sigma_deg=None if first is None else first.sigma_deg,
        gravity2_sigma_deg=None if second is None else second.sigma_deg,
        heading1=None if compass1 is None else compass1.deg,
        heading2=None if compass2 is None else compass2.deg,
        heading1_sigma_deg=None if compass1 is None else compass1.sigma_deg,
        heading2_sigma_deg=None if compass2 is None else compass2.sigma_deg,
    )


def fitted(
    taps: dict[Role, Taps | None],
    default_sigma: float,
    photos: PhotoFacts,
    *,
    known: KnownFit | None = None,
) -> tuple[SolveResult, PhotoOrder] | None:
    """The answer these taps give and whose photo was photo 1; None without one."""
    task = problem(taps, default_sigma, levelled=photos.levelled)
    if not task.solvable:
        return None
    try:
        return fit(task, photos, known=known), task.order
    except SolverError:
        return None


def answer(
    task: Problem,
    result: SolveResult,
    sizes: dict[Role, tuple[int, int]],
    *,
    drawn: dict[Role, AnswerDrawing] | None = None,
) -> Answer:
    """What each phone is told: where its friend is in its own photo. Photo 1's friend is
    the mark its phone tapped (refined by the fit), or the point the fit puts on its line,
    or (nothing marked) where the landmarks put them; photo 2's is what the fit found. Each
    gets the answer's drawing on its photo (``sizes``: width, height px), which it renders,
    and the warnings about its photo or about both (never by their sentences).

    ``drawn``: the drawings made already for this very task and result (a known fit's),
    used as they are when made for a photo of that size."""
    order = task.order

    def drawing(photo: PhotoNumber, points: list[Point]) -> AnswerDrawing:
        size = sizes[order.role(photo)]
        made = (drawn or {}).get(order.role(photo))
        if made is not None and (made.width, made.height) == size:
            return made
        landmarks = np.array(points, np.float64).reshape(-1, 2)
        return answer_drawing(result, photo=photo, size=size, landmarks=landmarks, labels=task.ids)

    def warnings(photo: PhotoNumber) -> list[SolverWarning]:
        return [warning for warning in result.warnings if warning.told_to(photo)]

    focal = [camera.focal_35mm for camera in result.cameras] or [None, None]
    focal_px = [camera.focal_px for camera in result.cameras] or [None, None]
    suspects = {task.ids[i] for i in result.suspect_landmarks}
    one = FriendInPhoto(
        friend=result.epipole1,
        friend_h=result.epipole1_h,
        how="marked" if task.epipole1 is not None else "on_line" if task.line1 else "solved",
        candidates=_others([c.epipole1 for c in result.candidates], result.epipole1),
        focal_35mm=focal[0],
        focal_px=focal_px[0],
        warnings=warnings(1),
        drawing=drawing(1, task.points1),
    )
    ellipse = result.uncertainty.ellipse if result.uncertainty else None
    two = FriendInPhoto(
        friend=result.epipole2,
        friend_h=result.epipole2_h,
        how="marked" if task.epipole2 is not None else "solved",
        region=ellipse,
        curve=result.conic2,
        level=result.curve2,
        level_halfwidth=result.curve2_halfwidth,
        level_stretch=result.curve2_stretch,
        candidates=_others([c.epipole2 for c in result.candidates], result.epipole2),
        focal_35mm=focal[1],
        focal_px=focal_px[1],
        warnings=warnings(2),
        drawing=drawing(2, task.points2),
    )
    return Answer(
        method=result.method,
        camera_model=result.camera_model,
        quality=result.quality,
        landmark_ids=task.ids,
        suspects=sorted(suspects),
        residuals=result.residuals,
        used_heading=result.used_heading,
        in_photo={order.first: one, order.second: two},
    )


def _known_drawings(task: Problem, known: KnownFit | None) -> dict[Role, AnswerDrawing] | None:
    """The drawings of ``known``'s answer when it answered this very task: a drawing is the
    result's, the task's landmarks and the photo's size alone, so it is the same again.
    Half of a search's tap writes change no matched landmark (one phone taps a landmark the
    other has not yet), and drawing both photos was a sixth of such a write's CPU."""
    if known is None or known.task != task or known.stored.answer is None:
        return None
    views = known.stored.answer.in_photo.items()
    return {role: view.drawing for role, view in views if view.drawing is not None}


def _others(positions: list[Point | None], answer: Point | None) -> list[Point]:
    """The positions other than the answer (within a pixel) that fit the taps as well."""
    return [
        p for p in positions if p is not None and (answer is None or math.dist(p, answer) > 1.0)
    ]
