"""A suggested spot for a landmark in the other photo, or none when the match is not sure.

A wrong suggestion is worse than none: a person may accept it with one tap, and a spot
along the band fits the answer wherever it is on it, so nothing flags it afterwards. A
match is suggested only when everything agrees (the rule and its thresholds were chosen
on rendered halls and arenas, and are measured on others, in docs/suggestions.md):

- its correlation is high (``min_score``);
- the band is not too wide there (``max_across``): a band many times the patch's width
  (few landmarks, quick taps) holds places beside the rows searched, never compared, and
  on rendered arenas every spot once offered beyond 3 % of the diagonal was in one;
- nothing else along the band comes close (``min_margin`` over the runner-up, beyond 1 %
  of the diagonal), the patch read as it is or reversed along the lines (:mod:`.search`):
  a row of seats, a repeated sign, a banner's mirrored print, the other corner of a mat
  turned 180 degrees give two places almost alike;
- searched back from photo B along its own band in photo A, the same way, the match leads
  to the tapped point again (within 1 % of A's diagonal), and as clearly (the same least
  score and margin): the left-right check, which a look-alike in photo A also defeats;
- or, where the small patch cannot tell two places apart, its context can: the patch
  twice the size scores at the match ``context_margin`` above any other place found
  (:mod:`.search`), and the search back leads to the tapped point again with the least
  score;
- in its context the match still scores ``min_context``: a look-alike of the patch with
  other surroundings does not;
- the search back scores about as the match does (``max_score_gap``): both are the same
  pair of patches;
- it is the patch as read: a match read reversed along the lines (a banner seen from
  behind, its print mirrored) would have to lead the patch as read anywhere by
  ``min_view_lead`` and not be beside it, and is not offered by default (a box's corner,
  a floor marking, a pillar's edge read the other way look alike too often);
- it lies in the band (the tap check of :meth:`.band.Band.check`), as a tap there would.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from ..projective import Array
from ..result import Pixel
from .band import FLAG_SIGMAS, Band, epipolar_band
from .epipolar import Epipolar
from .polar import Image, polar_frame
from .search import VIEWS, Match, best_match


@dataclass(frozen=True)
class Rules:
    """When a match is suggested, and how it is searched for.

    Attributes:
        min_score: least normalised cross-correlation of the match.
        min_margin: least lead of its score over the best elsewhere along the band.
        tolerance: fraction of a photo's diagonal within which two places are the same
            (the runner-up's exclusion, and the back-check's distance).
        radius: half size of the patch, px of the stored photo.
        max_margin: most rows searched on each side of the band's centre line.
        views: the views of the patch searched (:data:`.search.VIEWS`).
        min_view_lead: least lead of a match in another view than as read over the best
            place of the patch as read (infinite: never offered; docs/suggestions.md,
            section 5, weighs others).
        view_apart: least distance along the band between such a match and that place,
            fraction of the diagonal (closer, the two views disagree about one spot: the
            edge of a pillar, a mat's corner, read the other way).
        max_score_gap: most difference between the scores of the match and of the search
            back (the same pair of patches seen both ways should score alike; a search
            back far surer than the match went from a look-alike to its own twin).
        max_across: most half-width of the band at the match, in strip rows
            (:attr:`.search.Match.across`), for it to be offered: twice the rows searched
            on each side (``max_margin``). Wider (few landmarks, quick taps), the band
            holds many places beside the rows searched, never compared, and a look-alike
            among the rows searched leads (docs/geometry.md; infinite: no limit).
        context_radius: half size of the context's patch, px (``radius`` or less: no
            context, and a match must lead by ``min_margin``).
        context_margin: least lead of the match's context score over every other place's
            that stands in for ``min_margin`` (here and on the search back).
        min_context: least context score of a match offered.
    """

    min_score: float = 0.7
    min_margin: float = 0.05
    tolerance: float = 0.01
    radius: int = 16
    max_margin: int = 16
    views: tuple[str, ...] = tuple(VIEWS)
    min_view_lead: float = math.inf
    view_apart: float = 0.015
    max_score_gap: float = 0.2
    max_across: float = 32.0
    context_radius: int = 32
    context_margin: float = 0.1
    min_context: float = 0.3


RULES = Rules()


class Suggestion(BaseModel):
    """Where the landmark probably is in photo B, for the phone to offer."""

    model_config = ConfigDict(frozen=True)

    point: Pixel = Field(description="The suggested spot in photo B, stored-photo px.")
    score: float = Field(description="Normalised cross-correlation of the patches (-1 to 1).")
    margin: float = Field(description="Its lead over the best other place along the band.")


@dataclass(frozen=True)
class Evidence:
    """What the rule decides on.

    Attributes:
        match: the best place along the band (:func:`search_band`).
        sigmas: its distance from the band's centre line, in standard deviations of the
            line there and of a tap (what the tap check measures).
        back: the best place of the search back from it along its own band in photo A
            (:func:`search_back`; None when it finds nothing).
        returned: how far that lands from the tapped point, as a fraction of photo A's
            diagonal (infinite when it finds nothing).
    """

    match: Match
    sigmas: float
    back: Match | None = None
    returned: float = math.inf


@dataclass(frozen=True)
class LandmarkSearch:
    """One landmark's search: where it was tapped in photo A, and its band in photo B.

    Attributes:
        photo_a, photo_b: the stored photos, (H, W, 3) uint8 BGR (or (H, W) grey).
        point: (2,) where the landmark was tapped in A, px.
        epipolar: the answer's geometry from A to B, oriented by the shared landmarks.
        band: the landmark's band in B (:func:`.band.epipolar_band`).
        point_covariance: (2, 2) the tap's covariance, px^2 (for the tap check and the
            band of the search back from B to A).
    """

    photo_a: Image
    photo_b: Image
    point: Array
    epipolar: Epipolar
    band: Band
    point_covariance: Array = field(kw_only=True)


def suggest(search: LandmarkSearch, *, rules: Rules = RULES) -> Suggestion | None:
    """Search photo B's band for the landmark tapped in photo A.

    Args:
        search: the photos, the tap and its band.
        rules: the thresholds (the default is the calibrated one).

    Returns:
        The suggestion, or None when no place along the band is a sure match.
    """
    evidence = gather(search, rules=rules)
    if evidence is None or not offerable(evidence.match, rules):
        return None  # the search back is only worth its time for a match that may be offered
    return decide(check_back(evidence, search, rules=rules), rules)


def gather(search: LandmarkSearch, *, rules: Rules = RULES) -> Evidence | None:
    """The search along the band: the evidence before the search back; None when the band
    gives no place at all."""
    match = search_band(
        search.photo_a, search.photo_b, search.point, search.epipolar, search.band, rules=rules
    )
    if match is None:
        return None
    return Evidence(match, search.band.check(match.point, search.point_covariance).sigmas)


def check_back(evidence: Evidence, search: LandmarkSearch, *, rules: Rules = RULES) -> Evidence:
    """The evidence with the search back from its match (:func:`search_back`)."""
    found = search_back(search, evidence.match, rules=rules)
    if found is None:
        return evidence
    height, width = search.photo_a.shape[:2]
    returned = float(np.hypot(*(found.point - search.point))) / math.hypot(width, height)
    return replace(evidence, back=found, returned=returned)


def decide(evidence: Evidence, rules: Rules = RULES) -> Suggestion | None:
    """The suggestion the evidence allows under ``rules``, or None."""
    match, back = evidence.match, evidence.back
    if (
        not offerable(match, rules)
        or evidence.sigmas > FLAG_SIGMAS
        or back is None
        or evidence.returned > rules.tolerance
        or not (leads(back, rules) or (stands_out(match, rules) and clears(back, rules)))
        or abs(match.score - back.score) > rules.max_score_gap
    ):
        return None
    return Suggestion(
        point=(float(match.point[0]), float(match.point[1])),
        score=match.score,
        margin=match.score - match.runner_up,
    )


def leads(match: Match, rules: Rules = RULES) -> bool:
    """Whether a match clears the bar (:func:`clears`) and scores clearly above anything
    else on its band."""
    return clears(match, rules) and match.score - match.runner_up >= rules.min_margin


def clears(match: Match, rules: Rules = RULES) -> bool:
    """Whether a match scores high enough and, in a view other than as read, clearly above
    the patch as read anywhere and not beside it: :func:`leads` but for the runner-up."""
    return match.score >= rules.min_score and (
        match.view == "as read"
        or (
            match.score - match.as_read >= rules.min_view_lead
            and match.as_read_apart > rules.view_apart
        )
    )


def stands_out(match: Match, rules: Rules = RULES) -> bool:
    """Whether the match's context scores ``context_margin`` above every other place's
    (never without a context)."""
    return (
        rules.context_radius > rules.radius
        and match.context - match.context_runner_up >= rules.context_margin
    )


def offerable(match: Match, rules: Rules = RULES) -> bool:
    """Whether the match along the band may be offered, before its search back: it leads
    (:func:`leads`), or it clears the bar and stands out in its context (:func:`clears`,
    :func:`stands_out`); the band is not too wide there (``max_across``); and it keeps
    ``min_context`` in its context, where the rules have one (so not within two context
    radii of ``e_A``, where no context is read: a spot unchecked is not offered)."""
    return (
        (leads(match, rules) or (stands_out(match, rules) and clears(match, rules)))
        and match.across <= rules.max_across
        and (rules.context_radius <= rules.radius or match.context >= rules.min_context)
    )


def search_back(search: LandmarkSearch, match: Match, *, rules: Rules = RULES) -> Match | None:
    """The best place in A for the patch of B at ``match``, along its own band in A
    (None when that band misses A or holds no place)."""
    back = search.epipolar.transposed()
    height_a, width_a = search.photo_a.shape[:2]
    back_band = epipolar_band(
        back,
        match.point,
        image_size=(width_a, height_a),
        point_covariance=search.point_covariance,
    )
    if back_band is None:
        return None
    return search_band(
        search.photo_b, search.photo_a, match.point, back, back_band, rules=rules, context=False
    )


def search_band(
    photo_a: Image,
    photo_b: Image,
    point: Array,
    epipolar: Epipolar,
    band: Band,
    *,
    rules: Rules = RULES,
    context: bool = True,
) -> Match | None:
    """The best place along ``band`` for the patch at ``point`` (both halves of the line
    when ``epipolar`` is not oriented: each searched as a half-line from ``e_B``), each
    place scored in its context too (with ``context``, where ``rules`` have one)."""
    height_b, width_b = photo_b.shape[:2]
    exclusion = rules.tolerance * math.hypot(width_b, height_b)
    geometries = [epipolar] if epipolar.sign != 0 else [replace(epipolar, sign=s) for s in (1, -1)]
    found: list[Match] = []
    for geometry in geometries:
        frame = polar_frame(
            photo_a,
            photo_b,
            point,
            geometry,
            band,
            radius=rules.radius,
            max_margin=rules.max_margin,
        )
        if frame is None:
            continue
        ends = (np.array([band.start, band.end]) - frame.origin) @ geometry.direction(
            np.asarray(point, float)[None]
        )[0]
        low, high = max(0.0, float(ends.min())), float(ends.max())
        if high - low < 1.0:
            continue
        surroundings = None
        if context and rules.context_radius > rules.radius:
            surroundings = polar_frame(
                photo_a,
                photo_b,
                point,
                geometry,
                band,
                radius=rules.context_radius,
                max_margin=rules.max_margin,
            )
        match = best_match(
            frame,
            np.arange(low, high, 1.0),
            exclusion=exclusion,
            views=rules.views,
            context=surroundings,
        )
        if match is not None:
            found.append(match)
    if not found:
        return None
    found.sort(key=lambda match: -match.score)
    best = replace(found[0], as_read_apart=found[0].as_read_apart / math.hypot(width_b, height_b))
    if len(found) > 1:  # the other half-line's places compete as runners-up
        other = found[1]
        best = replace(
            best,
            runner_up=max(best.runner_up, other.score),
            context_runner_up=max(best.context_runner_up, other.context, other.context_runner_up),
        )
    return best
