"""What every section shares: seeds, one trial of one method (:class:`Outcome`), many
trials (:class:`Summary`), one call of ``solve`` on noisy taps, and the cells of the tables."""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal, Required, TypedDict, TypeVar, Unpack

import numpy as np
from report import markdown_table

from shared_solver import Camera, SolverError, SolveResult, solve
from shared_solver.projective import Array, to_pixel
from testbed.phones import PhoneScene
from testbed.scenes import Scene, Taps, line_through

# Chi-square quantile, 2 degrees of freedom, 95 %: -2 ln(0.05) = 5.991.
CHI2_2DOF_95 = -2.0 * math.log(0.05)

# Every random draw is seeded from (SEED, stream, ...): trial i of a stream is reproducible
# on its own, so a quick run with --trials N measures the first N trials of the full run.
SEED = 20240601
SCENE_STREAM = {
    "accuracy": 1,
    "coverage": 2,
    "planar": 3,
    "rank": 4,
    "speed": 5,
    "phone": 6,
    "zoom2": 7,
    "zoom3": 8,
    "kinds": 9,
    "speed phone": 10,
    "prior": 21,
}
TAP_STREAM = {
    "accuracy": 11,
    "coverage": 12,
    "planar": 13,
    "speed": 15,
    "phone": 16,
    "zoom2": 17,
    "zoom3": 18,
    "mixed": 19,
    "speed phone": 20,
    "prior": 22,
}

Given = Literal["e1", "line", "both", "none"]
# What solve is told about both cameras: nothing (projective), the phone prior, EXIF focal.
Cameras = Literal["unknown", "phone", "exif"]


# A report's target: whether it passed, and its line ("PASS: ...").
Target = tuple[bool, str]


@dataclass(frozen=True)
class Row:
    """A case of a section's table (each section adds what else it varies): the row's label
    and how many landmarks its solves are given."""

    label: str
    landmarks: int


def scene_rng(stream: str, trial: int, *extra: int) -> np.random.Generator:
    return np.random.default_rng((SEED, SCENE_STREAM[stream], *extra, trial))


def tap_rng(stream: str, sigma: float, trial: int) -> np.random.Generator:
    return np.random.default_rng((SEED, TAP_STREAM[stream], round(1000 * sigma), trial))


# --- what one trial gives ---------------------------------------------------------------


@dataclass(frozen=True)
class Outcome:
    """One method on one trial: error of e2 (inf if none), why there is none, the region,
    the method and camera model that answered."""

    error_px: float
    failure: str | None = None  # a refusal's code, or why the answer has no point
    covered: bool = False
    has_ellipse: bool = False
    method: str = ""
    camera_model: str = ""


@dataclass(frozen=True)
class Summary:
    """Many trials of one method in one cell of a table."""

    trials: int
    median: float
    p90: float
    failures: Counter[str]
    claims: int  # answers with a 95 % region
    coverage: float  # of those claims, the fraction that hold the truth
    methods: Counter[str] = field(default_factory=Counter)
    camera_models: Counter[str] = field(default_factory=Counter)
    # 95 % intervals of the median and the p90 of the population the trials were drawn from
    # (:func:`quantile_interval`): how far another seed could move them.
    median_interval: tuple[float, float] = (math.nan, math.nan)
    p90_interval: tuple[float, float] = (math.nan, math.nan)

    @classmethod
    def of(cls, outcomes: Sequence[Outcome]) -> Summary:
        errors = [o.error_px for o in outcomes]
        claims = sum(o.has_ellipse for o in outcomes)
        return cls(
            trials=len(outcomes),
            median=percentile(errors, 50),
            p90=percentile(errors, 90),
            median_interval=quantile_interval(errors, 0.5),
            p90_interval=quantile_interval(errors, 0.9),
            failures=Counter(o.failure for o in outcomes if o.failure is not None),
            claims=claims,
            coverage=sum(o.covered for o in outcomes) / max(1, claims),
            methods=Counter(o.method for o in outcomes if o.method),
            camera_models=Counter(o.camera_model for o in outcomes if o.camera_model),
        )

    @property
    def points(self) -> int:
        """Answers that put friend 1 at a point of photo 2."""
        return self.trials - sum(self.failures.values())


K = TypeVar("K")
S = TypeVar("S", bound=Scene)


def summaries(
    methods: Mapping[K, Callable[[S, Taps, float], Outcome]],
    draws: Iterable[tuple[S, Taps, float]],
) -> dict[K, Summary]:
    """Every method on every drawn (scene, taps, tap sigma), summarised per method."""
    outcomes: dict[K, list[Outcome]] = {name: [] for name in methods}
    for scene, taps, sigma in draws:
        for name, method in methods.items():
            outcomes[name].append(method(scene, taps, sigma))
    return {name: Summary.of(found) for name, found in outcomes.items()}


def percentile(values: Sequence[float], q: float) -> float:
    """numpy's linear-interpolation percentile, made safe for infinite errors."""
    ordered = np.sort(np.asarray(values, dtype=np.float64))
    position = q / 100.0 * (len(ordered) - 1)
    low, high = math.floor(position), math.ceil(position)
    if low == high:
        return float(ordered[low])
    if math.isinf(ordered[high]):
        return math.inf
    return float(ordered[low] + (position - low) * (ordered[high] - ordered[low]))


def quantile_interval(
    values: Sequence[float] | Array, q: float, level: float = 0.95
) -> tuple[float, float]:
    """A distribution-free ``level`` interval for the ``q``-quantile (0 < q < 1) of the
    population ``values`` were drawn from: two of their order statistics, X(r) <= X(s),
    which hold it between them with probability at least ``level``, since the count of
    values below it is binomial (n, q) (Conover, Practical Nonparametric Statistics, 3rd
    ed., section 3.2). Written out: the binomial's CDF is a few lines of numpy, and SciPy is
    not otherwise needed. Ends beyond the values are infinite (too few of them); empty: NaN.
    """
    ordered = np.sort(np.asarray(values, dtype=np.float64))
    n = len(ordered)
    if n == 0:
        return math.nan, math.nan
    k = np.arange(n + 1)
    log_pmf = (
        math.lgamma(n + 1)
        - np.array([math.lgamma(j + 1) + math.lgamma(n - j + 1) for j in k])
        + k * math.log(q)
        + (n - k) * math.log1p(-q)
    )
    cdf = np.cumsum(np.exp(log_pmf))  # P(B <= j), B the count below the quantile
    tail = (1.0 - level) / 2.0
    # X(r) <= quantile when B >= r; X(s) >= quantile when B <= s - 1 (ranks from 1).
    r = int(np.searchsorted(cdf, tail, side="right"))
    s = int(np.searchsorted(cdf, 1.0 - tail, side="left")) + 1
    low = float(ordered[r - 1]) if r >= 1 else -math.inf
    high = float(ordered[s - 1]) if s <= n else math.inf
    return low, high


def pixel_error(estimate_h: Sequence[float] | Array | None, truth: Array) -> float:
    """Distance (px) of a homogeneous estimate from the true pixel; inf at infinity or none."""
    if estimate_h is None:
        return math.inf
    pixel = to_pixel(np.asarray(estimate_h, dtype=np.float64))
    return math.inf if pixel is None else float(np.linalg.norm(pixel - truth))


def ellipse_covers(result: SolveResult, truth: Array) -> bool | None:
    """Whether the truth is inside the 95 % ellipse (chi-square, 2 dof); None: no ellipse."""
    uncertainty = result.uncertainty
    if uncertainty is None or uncertainty.ellipse is None or uncertainty.covariance is None:
        return None
    offset = truth - np.asarray(uncertainty.ellipse.center)
    try:
        distance = offset @ np.linalg.solve(np.asarray(uncertainty.covariance), offset)
    except np.linalg.LinAlgError:
        return False
    return bool(distance <= CHI2_2DOF_95)


# --- one call of solve ------------------------------------------------------------------


@dataclass(frozen=True)
class Precisions:
    """Each tap's own sigma (px), told to ``solve``: (N,) per landmark, one per friend."""

    points1: Array
    points2: Array
    epipole1: float
    epipole2: float


def mixed_taps(
    scene: Scene, rng: np.random.Generator, sigmas: tuple[float, float]
) -> tuple[Taps, Precisions]:
    """Taps of mixed precision: each tap (landmarks and both friends) at one of ``sigmas``
    px, at even odds, with Gaussian noise of that sigma."""
    n = len(scene.points)
    low, high = sigmas
    s1, s2 = (np.where(rng.random(n) < 0.5, high, low) for _ in range(2))
    e1_sigma, e2_sigma = (float(high if rng.random() < 0.5 else low) for _ in range(2))
    taps = Taps(
        scene.landmarks1 + rng.normal(size=(n, 2)) * s1[:, None],
        scene.landmarks2 + rng.normal(size=(n, 2)) * s2[:, None],
        scene.epipole1 + rng.normal(0.0, e1_sigma, 2),
        scene.epipole2 + rng.normal(0.0, e2_sigma, 2),
    )
    return taps, Precisions(s1, s2, e1_sigma, e2_sigma)


def camera_pair(
    cameras: Cameras, exif: tuple[float, float] | None
) -> tuple[Camera | str | None, Camera | str | None]:
    """What ``solve`` is told about the two cameras; ``exif``: their focal lengths (35 mm
    equivalent) as EXIF gives them, needed for ``exif``."""
    if cameras == "phone":
        return "phone", "phone"
    if cameras == "exif":
        assert exif is not None
        return Camera.with_focal(exif[0]), Camera.with_focal(exif[1])
    return None, None


class Asked(TypedDict, total=False):
    """What else ``solve`` is told besides the landmarks: what is marked (``given``), the
    angle of a friend's line, the cameras, each tap's own precision."""

    given: Required[Given]
    line_angle: float
    cameras: Cameras
    precisions: Precisions | None


def solve_arguments(
    scene: Scene, taps: Taps, sigma: float, landmarks: int, **asked: Unpack[Asked]
) -> tuple[tuple[Array, Array], dict[str, Any]]:
    """The arguments of ``shared_solver.solve`` for the first ``landmarks`` taps and what else
    is given: built once, so that timing a call times ``solve`` alone."""
    given, precisions = asked["given"], asked.get("precisions")
    line = line_through(taps.epipole1, asked.get("line_angle", 0.0))
    exif = None
    if isinstance(scene, PhoneScene):
        exif = (scene.exif_focal_35mm1, scene.exif_focal_35mm2)
    camera1, camera2 = camera_pair(asked.get("cameras", "unknown"), exif)
    both = given == "both"
    options: dict[str, Any] = {
        "epipole1": taps.epipole1 if given in ("e1", "both") else None,
        "epipole2": taps.epipole2 if both else None,
        "epipolar_line1": line if given == "line" else None,
        "tap_sigma": sigma,
        **scene.sizes,
        "camera1": camera1,
        "camera2": camera2,
        "points1_sigma": None if precisions is None else precisions.points1[:landmarks],
        "points2_sigma": None if precisions is None else precisions.points2[:landmarks],
        "epipole1_sigma": None if precisions is None else precisions.epipole1,
        "epipole2_sigma": None if precisions is None or not both else precisions.epipole2,
    }
    return (taps.landmarks1[:landmarks], taps.landmarks2[:landmarks]), options


def solve_call(
    scene: Scene, taps: Taps, sigma: float, landmarks: int, **asked: Unpack[Asked]
) -> SolveResult:
    """``shared_solver.solve`` on the first ``landmarks`` taps and what else is given."""
    points, options = solve_arguments(scene, taps, sigma, landmarks, **asked)
    return solve(*points, **options)


def ours(scene: Scene, taps: Taps, sigma: float, landmarks: int, **asked: Unpack[Asked]) -> Outcome:
    """:func:`solve_call` graded against the scene's true e2."""
    try:
        result = solve_call(scene, taps, sigma, landmarks, **asked)
    except SolverError as error:
        return Outcome(math.inf, failure=error.code.value)
    truth = scene.epipole2
    covered = ellipse_covers(result, truth)
    return Outcome(
        pixel_error(None if result.epipole2 is None else (*result.epipole2, 1.0), truth),
        failure=no_point(result),
        covered=bool(covered),
        has_ellipse=covered is not None,
        method=result.method,
        camera_model=result.camera_model,
    )


def no_point(result: SolveResult) -> str | None:
    """Why an answer puts friend 1 at no point of photo 2; None when it does."""
    if result.epipole2 is not None:
        return None
    if result.epipole2_h is None:
        return "no point (a curve)" if result.conic2 is not None else "no point"
    h = np.asarray(result.epipole2_h)
    if to_pixel(h) is None:
        return "at infinity"
    # "Behind you": friend 1 behind friend 2's camera. Never true in these scenes.
    return "behind friend 2"


# --- cells of the tables ------------------------------------------------------------------


def fmt(value: float) -> str:
    """An error in px: 3 significant figures is all 500 trials support."""
    if math.isinf(value) or math.isnan(value):
        return "inf"
    return f"{value:.2f}" if value < 10 else f"{value:.1f}" if value < 100 else f"{value:.0f}"


def interval(bounds: tuple[float, float]) -> str:
    """An interval of errors in px, as :func:`fmt` writes each end."""
    return f"{fmt(bounds[0])}-{fmt(bounds[1])}"


def percent(fraction: float) -> str:
    return f"{100 * fraction:.1f} %"


def failures(summary: Summary) -> str:
    """Refusals (by code) and answers without a point (at infinity, behind friend 2, a curve
    only); all count as infinite error."""
    parts = [f"{count} {code}" for code, count in summary.failures.most_common()]
    return ", ".join(parts) if parts else "0"


def coverage_cell(summary: Summary) -> str:
    """Coverage of the regions claimed, and how many answers claimed one."""
    if summary.claims == 0:
        return "no region claimed"
    return f"{percent(summary.coverage)} of {summary.claims}"


def methods_cell(summary: Summary) -> str:
    return ", ".join(f"{name} {count}" for name, count in summary.methods.most_common()) or "-"


def fell_back(summary: Summary) -> int:
    """Answers of the camera-aware route that came from the projective geometry."""
    return summary.camera_models["projective"]


def cases_table(second: str, rows: Iterable[tuple[str, str, Summary]]) -> str:
    """One row per case: its label, the ``second`` column (sigma or trials), the error's
    median and p90, the regions' coverage, the methods that answered and the failures."""
    header = ["case (landmarks + given)", second, "median", "p90", "95 % coverage"]
    return markdown_table(
        [*header, "method used", "failures"],
        [
            [label, cell, fmt(s.median), fmt(s.p90), coverage_cell(s), methods_cell(s), failures(s)]
            for label, cell, s in rows
        ],
    )


def errors_cell(summary: Summary) -> str:
    return f"{fmt(summary.median)} / {fmt(summary.p90)}"
