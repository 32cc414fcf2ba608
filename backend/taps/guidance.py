"""Helping a phone find the next landmark, once there is an answer (docs/geometry.md,
"Finding a landmark in the other photo").

Every landmark one phone has tapped and the other has not lies on a known epipolar line in
the other photo: its **band** (that line widened by the answer's uncertainty and the tap's)
is sent with the answer, for the phone that still has to find it. A landmark a phone taps
far outside its band is **flagged** ("#4 does not fit the others"), judged against the
answer from before that tap, which the tap has not pulled yet. A **suggested spot**, the
other photo's patch found along the band, costs an image search (tens of ms), so it is
computed only when a phone asks for it (:class:`Suggestions`, kept per answer).

All positions are in stored-photo pixels; ``order`` says whose photo is the answer's photo 1.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Mapping
from threading import Lock
from typing import Any

import numpy as np

from backend.participants import ROLES, Role, other
from shared_solver import SolveResult
from shared_solver.matching import Epipolar, epipolar_band, guide_landmark
from shared_solver.matching.band import BandShape

from .photo_order import PhotoOrder
from .schemas import Landmark, StoredAnswer, Taps

Point = tuple[float, float]
# How many answers' suggestions a process keeps (a few per search being tapped).
_KEPT_ANSWERS = 256


def bands(
    result: SolveResult,
    order: PhotoOrder,
    taps: Mapping[Role, Taps | None],
    sizes: Mapping[Role, tuple[int, int]],
    default_sigma: float,
) -> dict[Role, dict[int, BandShape]]:
    """For each phone, the bands in its photo of the landmarks only the other phone tapped."""
    shared1, shared2 = _shared(taps, order)
    found: dict[Role, dict[int, BandShape]] = {role: {} for role in ROLES}
    for role in ROLES:
        mine, theirs = taps[role], taps[other(role)]
        if theirs is None:
            continue
        have = {tap.id for tap in mine.landmarks} if mine is not None else set()
        epipolar = Epipolar.from_result(
            result, tapped_in=order.number(other(role)), landmarks1=shared1, landmarks2=shared2
        )
        if epipolar is None:
            continue
        for tap in theirs.landmarks:
            if tap.id in have:
                continue
            sigma = tap.sigma or default_sigma
            band = epipolar_band(
                epipolar,
                np.array([tap.x, tap.y]),
                image_size=sizes[role],
                point_covariance=sigma**2 * np.eye(2),
            )
            if band is not None:
                found[role][tap.id] = band.shape()
    return found


def misfits(
    previous: StoredAnswer | None,
    before: Mapping[Role, Taps | None],
    after: Mapping[Role, Taps | None],
    *,
    sizes: Mapping[Role, tuple[int, int]],
    default_sigma: float,
    fit: Callable[[dict[Role, Taps | None]], tuple[SolveResult, PhotoOrder] | None],
) -> dict[Role, list[int]]:
    """Each phone's landmark taps that do not fit the others.

    A landmark tapped or moved since ``before`` is judged against the answer the *other*
    landmarks give (``fit``: the taps -> that answer and whose photo was photo 1), so a
    wrong tap cannot vouch for itself; one unchanged keeps the verdict it had in
    ``previous``, the stored answer before this change (one solve per changed tap, not per
    tap).
    """
    told = None if previous is None else previous.answer
    views = {} if told is None else told.in_photo
    verdicts: dict[Role, list[int]] = {}
    for role in ROLES:
        now, was, theirs = after[role], before[role], after[other(role)]
        if now is None or theirs is None:
            verdicts[role] = []
            continue
        old = {t.id: (t.x, t.y) for t in was.landmarks} if was is not None else {}
        partners = {t.id: t for t in theirs.landmarks}
        view = views.get(role)
        flagged = set() if view is None else set(view.misfits)
        for tap in now.landmarks:
            if old.get(tap.id) == (tap.x, tap.y):
                continue  # unchanged: its verdict stands
            flagged.discard(tap.id)
            partner = partners.get(tap.id)
            if partner is not None and not _fits(
                tap,
                partner,
                role=role,
                taps=after,
                sizes=sizes,
                default_sigma=default_sigma,
                fit=fit,
            ):
                flagged.add(tap.id)
        verdicts[role] = sorted(flagged & {t.id for t in now.landmarks})
    return verdicts


def _fits(
    tap: Landmark,
    partner: Landmark,
    *,
    role: Role,
    taps: Mapping[Role, Taps | None],
    sizes: Mapping[Role, tuple[int, int]],
    default_sigma: float,
    fit: Callable[[dict[Role, Taps | None]], tuple[SolveResult, PhotoOrder] | None],
) -> bool:
    """Whether ``role``'s ``tap`` lies in the band of its ``partner`` under the answer of
    the other landmarks (True when they give none: nothing to judge it by)."""
    mine = taps[role]
    assert mine is not None
    others = dict(taps)
    others[role] = mine.model_copy(
        update={"landmarks": [t for t in mine.landmarks if t.id != tap.id]}
    )
    answered = fit(others)
    if answered is None:
        return True
    result, order = answered
    shared1, shared2 = _shared(others, order)
    epipolar = Epipolar.from_result(
        result,
        tapped_in=order.number(other(role)),
        landmarks1=shared1,
        landmarks2=shared2,
    )
    if epipolar is None:
        return True
    band = epipolar_band(
        epipolar,
        np.array([partner.x, partner.y]),
        image_size=sizes[role],
        point_covariance=(partner.sigma or default_sigma) ** 2 * np.eye(2),
    )
    sigma = tap.sigma or default_sigma
    return band is None or band.check(np.array([tap.x, tap.y]), sigma**2 * np.eye(2)).fits


def _shared(taps: Mapping[Role, Taps | None], order: PhotoOrder) -> tuple[np.ndarray, np.ndarray]:
    """(N, 2), (N, 2): the landmarks both photos share, in photo 1 and in photo 2."""
    one, two = taps.get(order.first), taps.get(order.second)
    if one is None or two is None:
        return np.zeros((0, 2)), np.zeros((0, 2))
    mine = {t.id: (t.x, t.y) for t in one.landmarks}
    theirs = {t.id: (t.x, t.y) for t in two.landmarks}
    ids = sorted(mine.keys() & theirs.keys())
    return np.array([mine[i] for i in ids]).reshape(-1, 2), np.array(
        [theirs[i] for i in ids]
    ).reshape(-1, 2)


class Suggestions:
    """Suggested spots, computed on demand and kept per (session, answer version, photo,
    landmark): phones ask again after a reconnect, and replicas each keep their own."""

    def __init__(self) -> None:
        self._kept: OrderedDict[tuple[str, int, str, int], Point | None] = OrderedDict()
        self._lock = Lock()

    def get(
        self, key: tuple[str, int, str, int], compute: Callable[[], Point | None]
    ) -> Point | None:
        with self._lock:
            if key in self._kept:
                self._kept.move_to_end(key)
                return self._kept[key]
        found = compute()
        with self._lock:
            self._kept[key] = found
            while len(self._kept) > _KEPT_ANSWERS:
                self._kept.popitem(last=False)
        return found


def suggested(
    solution: Mapping[str, Any],
    order: PhotoOrder,
    taps: Mapping[Role, Taps | None],
    photos: Mapping[Role, np.ndarray],
    *,
    finder: Role,
    landmark_id: int,
    default_sigma: float,
) -> Point | None:
    """Where landmark ``landmark_id``, tapped by the other phone, probably is in
    ``finder``'s photo: a sure match along its band, or None."""
    theirs = taps.get(other(finder))
    tap = next((t for t in theirs.landmarks if t.id == landmark_id), None) if theirs else None
    if tap is None:
        return None
    shared1, shared2 = _shared(taps, order)
    photo1, photo2 = photos[order.first], photos[order.second]
    guide = guide_landmark(
        SolveResult.model_validate(solution),
        photo1,
        photo2,
        np.array([tap.x, tap.y]),
        tapped_in=order.number(other(finder)),
        tap_sigma=tap.sigma or default_sigma,
        landmarks1=shared1,
        landmarks2=shared2,
    )
    if guide is None or guide.suggestion is None:
        return None
    x, y = guide.suggestion.point
    return float(x), float(y)
