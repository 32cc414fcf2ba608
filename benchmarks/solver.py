"""Buddy Search solver benchmark: accuracy, honesty of the 95 % ellipse, ranking and speed,
in one run.

What is measured, all in one process, with Gaussian tap noise on every tap (the friends'
marks included) and the same scenes and taps for every method of a trial:

1. Phone scenes (:func:`testbed.phones.phone_scene`: 12 MP photos, landscape or portrait,
   ~26 mm lenses, 20-80 m apart, facing by hand) at tap noise 1, 3 and 8 px: the projective
   route (5 and 8 landmarks + the tap e1 on friend 2), the camera-aware route with the phone prior
   (3, 4, 5, 8 + e1) and with the EXIF focal length (3, 4, 5 + e1), against OpenCV's
   5-point essential matrix with the true intrinsics (5 and 8 landmarks) and its 8-point
   fundamental matrix: e2 error, failures, coverage of every claimed 95 % region.
2. Photo 2 zoomed 2x and 3x without EXIF: camera-aware (phone prior) against projective.
3. Coverage of the camera-aware route case by case at 3 px, with more trials.
4. Ranking on exact input (a line + 6 landmarks, 7 landmarks with nothing marked) on every
   kind of :data:`testbed.kinds.SCENE_KINDS`: is the answer the true root, cameras unknown
   and with the phone prior.
5. The simple facing scenes (:func:`testbed.scenes.facing_scene`) of the first version:
   the projective route against OpenCV's 7- and 8-point methods at 0.5-5 px, and
6. the coverage of every projective method there.
7. Speed of ``solve`` in every case above and of ``epipole_from_five`` against
   ``cv2.findFundamentalMat`` with ``FM_7POINT``, timed interleaved in the same process.
8. Every camera-aware case against the Cramér-Rao bound of its taps.
9. Both phones' gravity at the shutter: each few-landmark case with and without it.

Seeds are fixed, so reruns give the same accuracy, coverage and ranking figures; trial ``i``
always uses the same scene and taps, whatever ``--trials`` says. Run from the repository
root:

    .venv/bin/python benchmarks/solver.py [--trials N] [--out PATH]     (``make bench``)

The report is printed and written as Markdown to ``docs/solver-benchmark.md``.
"""

from __future__ import annotations

import platform
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np
from report import ROOT, command_line, heading, machine, publish, source_state, timed
from solverbench import facing, gravity, limit, phones, ranking
from solverbench.common import SCENE_STREAM, SEED, TAP_STREAM
from solverbench.speed import (
    BATCH_SECONDS,
    REFERENCE_SEVEN_US,
    SOLVE_BUDGET_US,
    SpeedResult,
    speed,
    speed_table,
    speed_targets,
)

DEFAULT_OUT = ROOT / "docs" / "solver-benchmark.md"
DEFAULT_TRIALS = 500


@dataclass(frozen=True)
class Options:
    """What ``main`` takes: each field is an option of the same name (``--rank-scenes``);
    the defaults are the full run's."""

    trials: int = DEFAULT_TRIALS
    coverage_trials: int = 2 * DEFAULT_TRIALS
    rank_scenes: int = 300
    speed_scenes: int = 20
    speed_rounds: int = 25
    limit_trials: int = 1000
    # Section 9's targets sit within a few px of their medians: at 500 trials a median's
    # 95 % interval spanned 85.7-113 px around a 100 px target; 2000 halve it (the
    # section took 447 s at c3c4bca, 110 s at 500).
    gravity_trials: int = 2000


@dataclass(frozen=True)
class Results:
    options: Options
    phone_table: phones.PhoneTable
    zoom_table: phones.ZoomTable
    coverage_table: phones.CoverageTable
    rank_table: ranking.RankTable
    facing_table: facing.AccuracyTable
    facing_coverage: facing.CoverageTable
    six_point_rank: facing.RankCount
    speed_result: SpeedResult
    limit_table: limit.LimitTable
    gravity_table: gravity.GravityTable
    seconds: dict[str, float]


def header(options: Options) -> str:
    return "\n".join(
        [
            *heading("Solver benchmark", "benchmarks/solver.py", "bench"),
            machine(),
            f"- Python {platform.python_version()}, numpy {np.__version__}, "
            f"OpenCV {cv2.__version__}",
            f"- shared_solver: {source_state('shared_solver')}",
            f"- Trials: {options.trials} per cell in sections 1, 2, 5 and 6; "
            f"{options.coverage_trials} per case in section 3; {options.rank_scenes} scenes per "
            f"kind in section 4 and in the six_point_line rank check; speed: "
            f"{options.speed_scenes} scenes per case, {options.speed_rounds} rounds; "
            f"{options.limit_trials} per case and tap noise in section 8; "
            f"{options.gravity_trials} per case and gravity sigma in section 9"
            + (
                " (the defaults: no section was cut short for time)."
                if options == Options()
                else "."
            ),
            f"- Seeds: numpy default_rng((SEED={SEED}, stream, ...)); scenes "
            f"(SEED, stream, trial) (section 4: (SEED, stream, kind index, trial)), taps "
            f"(SEED, stream, round(1000 sigma), trial); scene streams {SCENE_STREAM}, tap "
            f"streams {TAP_STREAM}",
            "- Phone scenes: `testbed.phones.phone_scene` with 8 landmarks (each method uses the "
            "first ones): 4032x3024 photos, landscape or portrait at even odds, 26 mm +-5 % "
            "(35 mm equivalent), principal point off centre by 0.3 % of the diagonal, 20-80 m "
            "apart, each phone aimed at the other by hand. Facing scenes: "
            "`testbed.scenes.facing_scene` (1600x1200, f = 1400 px, 40 m apart). Gaussian tap "
            "noise sigma px per axis on every landmark tap and on both epipole taps; "
            "`tap_sigma=sigma` and both image sizes passed to `solve`.",
            "- Routes: *projective*: `camera1`/`camera2` not given (unknown); *phone prior*: "
            '`camera1="phone", camera2="phone"`; *EXIF focal*: '
            "`Camera.with_focal(scene.exif_focal_35mm1)` and `...2` (the true focal length "
            "rounded to a whole mm).",
        ]
    )


COVERAGE_NOTE = (
    "Failures: refusals (`SolverError` code, or OpenCV returning no matrix) and answers "
    "that put friend 1 at no point of photo 2 (`epipole2` null: at infinity, behind "
    "friend 2, or a curve only); all count as infinite error in the median and p90 (the "
    "true friend 1 is always in front, inside photo 2). Coverage: of the answers that "
    "claim a 95 % region "
    "(`result.uncertainty.ellipse` not null), the fraction whose true e2 is inside it "
    "(`result.uncertainty.covariance`, chi-square 2 dof 5.991), and how many claimed one; an "
    "answer without a region (ambiguous, or a method that claims none) claims nothing. "
    "*Answered by the projective route*: camera-aware calls whose taps disagreed with the "
    "camera model, so `solve` answered with the projective geometry (`camera_model` "
    "'projective'), saying so."
)


def report(results: Results) -> str:
    options = results.options
    targets: list[tuple[bool | None, str]] = [
        *phones.accuracy_targets(results.phone_table),
        phones.zoom_target(results.zoom_table),
        *ranking.rank_targets(results.rank_table),
        *speed_targets(results.speed_result.timings),
        facing.accuracy_target(results.facing_table),
        *limit.limit_targets(results.limit_table),
        *gravity.gravity_targets(results.gravity_table),
    ]
    seconds = ", ".join(f"{name} {s:.1f} s" for name, s in results.seconds.items())
    sections = [
        header(options),
        "## 1. Phone scenes: accuracy of e2 against OpenCV (same scenes, same noisy taps)",
        "e2 error in px, **median / 90th percentile**. One phone scene of 8 landmarks and its "
        "noisy taps per trial (the same scene at every sigma); each method uses the first "
        "3/4/5/8 landmarks. Ours also uses the noisy tap e1 on friend 2; OpenCV does not. OpenCV's "
        "essential matrix gets the **true intrinsics**: taps normalised with each camera's K, "
        "then `findEssentialMat(..., focal=1, pp=(0, 0), method=RANSAC, threshold=3 sigma / "
        "f)`. On 5 landmarks it returns every root of the 5-point solver, stacked: the table "
        "takes the **best root by oracle** (the one whose e2 = K2 (left null vector of E) is "
        "nearest the truth), which flatters OpenCV. On 8 landmarks RANSAC returns one E (its "
        "LMEDS was measured far worse here: every 5-landmark sample fits 5 of the 8 taps "
        "exactly, so the median error is 0 whatever the sample). OpenCV 8-point: "
        "`findFundamentalMat(..., FM_8POINT)` in pixels, e2 the left null vector of F. "
        "*Exact roots 3+e1, true K*: every rotation of our three-landmark solver "
        "(`minimal/epipole_and_three.py`) on the same noisy taps at the **true** intrinsics, "
        "principal points included, and the root nearest the truth (oracle): with no landmark "
        "to spare every estimator answers with one of these roots, so this bounds what 3 + e1 "
        "can give.",
        phones.accuracy_tables(results.phone_table),
        COVERAGE_NOTE,
        "## 2. Zoomed photos without EXIF",
        f"Photo 2 zoomed 2x and 3x (`phone_scene(zoom2=...)`), tap noise "
        f"{phones.TARGET_SIGMA:g} px, no EXIF: the camera-aware route with the phone prior "
        "against the projective route, on the same scenes and taps per trial.",
        phones.zoom_table(results.zoom_table),
        f"## 3. Coverage of the camera-aware route, case by case ({phones.TARGET_SIGMA:g} px)",
        f"{options.coverage_trials} trials per case. The plain cases use the phone scenes "
        f"and the {phones.TARGET_SIGMA:g} px taps of section 1 (trial i is the same; section "
        "1 has the first of them); the line goes through the noisy e1 tap in a random "
        "direction; both marked: the noisy e2 tap too. Mixed precision: the same scenes, "
        f"each tap (landmarks and both friends) at {phones.MIXED_SIGMAS[1]:g} px or "
        f"{phones.MIXED_SIGMAS[0]:g} px at even odds, told to `solve` by `points1_sigma`, "
        "`points2_sigma` and `epipole1_sigma`. Zoomed: the scenes and taps of section 2. "
        "*Focal lengths drawn from the prior*: phone scenes (own stream) whose two photos are "
        "zoomed by factors drawn from the phone prior itself (log-normal, sd 0.5: ultra-wide to "
        "4x), the scenes on which the prior is exactly right; on main-camera scenes the same "
        "prior is broader than the truth, so its regions there may hold the truth a little "
        "more often than 95 %. Errors in px.",
        phones.coverage_table(results.coverage_table),
        "## 4. Ranking on exact input: is the answer the true root?",
        f"Noise-free taps, `tap_sigma={ranking.TAP_SIGMA:g}`, {options.rank_scenes} scenes "
        "of each kind of `testbed.kinds.SCENE_KINDS` with 7 landmarks (the line + 6 case "
        "uses the first 6 and a line through the true e1 in a random direction). *venue* is "
        "`phone_scene` with main cameras: the phone scenes of sections 1 and 3. Every exact "
        "root comes from `six_point_line_roots(line, p, q)` or `seven_point_roots(p, q)`; the "
        "true root is the one whose F is nearest the scene's true F; the answer is the true "
        "root when the root nearest the answer's `fundamental` is that same root (F compared "
        "in Hartley-normalised coordinates, unit norm, either sign; the camera-aware answer "
        "is a refined fit, not exactly a root). *Of scenes with several roots*: the same "
        "where choosing mattered. *Truth not among the roots*: no root within "
        f"{ranking.FOUND_GAP:g} of the true F (none expected).",
        ranking.rank_table(results.rank_table),
        "## 5. Facing scenes: accuracy of e2 against OpenCV (same scenes, same noisy taps)",
        "The scenes of the first version, projective route only. e2 error in px, "
        "**median / 90th percentile**. One scene of 8 landmarks and its noisy taps per "
        "trial; each method uses the first 5/6/7/8 landmarks. Ours also uses the noisy tap "
        "e1 on friend 2; OpenCV does not. OpenCV 7-point returns 1 or 3 roots: the table takes the "
        "**best root by oracle** (the one whose e2 is closest to the truth), which flatters "
        "OpenCV. OpenCV's e2 is the left null vector of F (F^T e2 = 0).",
        facing.accuracy_tables(results.facing_table),
        "Failures and coverage as in section 1.",
        "## 6. Facing scenes: every projective method, and the regions it claims",
        "One 12-landmark scene and one set of noisy taps per trial, shared by the non-planar "
        "cases (each uses the first landmarks); a separate floor scene of 6 landmarks "
        "(`planar=True`) for planar. The line for six_point_line goes through the noisy e1 "
        "tap in a random direction. Errors in px. By design `six_point_line` and `seven_point` "
        "claim no region (first order and a bootstrap were both measured too optimistic "
        "for them); their answers are graded 'poor' and ask for friend 2 to be marked.",
        facing.coverage_table(results.facing_coverage),
        facing.rank_lines(results.six_point_rank),
        "## 7. Speed (same process, interleaved)",
        f"`solve` per call on {results.speed_result.phone_scenes} phone scenes (taps at "
        f"{phones.TARGET_SIGMA:g} px; the zoomed case on as many zoomed scenes, the mixed one "
        f"on taps of mixed precision) and on {results.speed_result.facing_scenes} facing scenes "
        "(1 px); `epipole_from_five` and OpenCV's 7-point call on the facing scenes (OpenCV "
        "gets the same first 7 landmarks, no e1). Each call is timed on each scene "
        f"separately, in {results.speed_result.rounds} interleaved rounds (a call shorter than "
        f"{BATCH_SECONDS * 1000:g} ms repeated to fill that, garbage collector off; the "
        "arguments are built beforehand); a scene's time is its median over rounds, and "
        "the table gives the **median call** over scenes (used for the targets), the 90th "
        "percentile over scenes (the slow tail: a start far from the answer costs the fit "
        "more steps) and the mean, in microseconds. The budget of `solve` is "
        f"{SOLVE_BUDGET_US / 1000:g} ms at the speed of the run it was set on, where OpenCV's "
        f"7-point call took {REFERENCE_SEVEN_US:g} us, scaled by that call's time in this run "
        "(this machine's speed changes by up to 2.3 times between runs).",
        speed_table(results.speed_result.timings),
        "## 8. At the limit: against the Cramér-Rao bound of the taps",
        f"{options.limit_trials} trials per case and tap noise: the phone scenes and taps of "
        "section 1 (trial i is the same; section 1 has the first of them). Each answer's "
        "error is compared with the Cramér-Rao bound of its own scene and taps "
        "(`testbed/bound.py`: the Fisher information of the tap model at the true geometry, "
        "the landmarks' 3-D points as nuisance unknowns, the focal prior as information: log "
        "sd 0.5 for the phone prior, 0.02 for EXIF; the camera-unknown bound has five free "
        "intrinsics per camera and no prior). *Median ratio*: the median error over the "
        "median of the bound's median errors; *RMS ratio*: the root mean square of error / "
        "the bound's RMS over answers with a point (1.0 is the limit; wild answers show here "
        "first); *area ratio*: the median of the 95 % region's area over the bound's 95 % "
        "ellipse (where it is over the target, the targets also say how often the same "
        "regions, each resized to the target's area knowing its scene's bound, would hold "
        "the truth: a region smaller than an estimator's errors cannot be honest, and an "
        "estimator's errors exceed the bound where it is not efficient); *told the model "
        "does not fit*: honest searches whose answer says the taps "
        "do not (quite) fit two phone photos (`CAMERA_MODEL_DISAGREES` or "
        "`CAMERA_MODEL_UNSURE`), the camera model's false alarms.",
        limit.limit_table(results.limit_table),
        "## 9. Gravity at the shutter",
        f"{options.gravity_trials} trials per case and sensor row: the phone scenes and "
        f"{phones.TARGET_SIGMA:g} px taps of section 1 (trial i is the same; the 'drawn from "
        "it' row: section 3's scenes whose focal lengths are drawn from the phone prior), each "
        "phone's reading its true down turned by Gaussian noise of the sigma per axis and "
        "told to `solve` (`gravity1`, `gravity2`, `gravity_sigma_deg`); *none*: the same "
        "taps without gravity (from three landmarks: fewer answer nothing). With no landmark "
        "the answer is the band around the level (`curve2`): its error is the truth's "
        "distance from the curve, it holds the truth within `curve2_halfwidth`, and the "
        "half-width is also given as an angle of photo 2's view. Otherwise a point, graded "
        "as in section 1 (failures count as infinite error), and against the Cramér-Rao "
        "bound of its scene as in section 8, the readings in the tap model (two unknowns "
        "more, the true down; each reading measures it across itself at its sigma; "
        "`SceneBounds.bound(gravity_sigma_deg=)`): the median error over the median of the "
        "bound's, and that median. One landmark with the EXIF focal is exactly determined "
        "(10 measurements, 10 unknowns): no estimator does better than the exact root, and "
        "the median sits at the bound's. With the phone prior the ratio can fall below 1: "
        "the scenes' focal lengths are the prior's centre, which a fit pulled towards it "
        "finds more easily than the unbiased estimators the bound speaks of. "
        "*Answers using gravity*: those "
        "whose readings were not dropped as contradicting the landmarks (`used_gravity`). "
        "Time: each call once, `time.perf_counter`, the median over trials (for scale "
        "only: section 7 times the gravity cases against the budget, interleaved). "
        "*Compass sigma*: both phones' compass headings too, each its lens's true heading "
        "with Gaussian noise of that sigma, told to `solve` (`heading1`, `heading2`, "
        "`heading_sigma_deg`); no bound is computed for them. With no landmark they add a "
        "stretch of the band (`curve2_stretch`, a hint): it holds the truth when the truth "
        "is within the band's half-width of it; its length is an angle of photo 2's view. "
        "*(N compass)*: answers whose headings were not dropped as contradicting the "
        "landmarks (`used_heading`).",
        gravity.gravity_table(results.gravity_table),
        "## Targets",
        "\n".join(f"- {line}" for _, line in targets),
        f"Wall time of the measurements: {sum(results.seconds.values()):.1f} s ({seconds}; "
        "interpreter start-up and imports not included).",
    ]
    return "\n\n".join(sections) + "\n"


def run(options: Options) -> Results:
    seconds: dict[str, float] = {}
    n, rank_scenes = options.trials, options.rank_scenes
    return Results(
        options,
        phone_table=timed(seconds, "1. phones", lambda: phones.accuracy(n)),
        zoom_table=timed(seconds, "2. zoomed", lambda: phones.zoomed(n)),
        coverage_table=timed(
            seconds, "3. coverage", lambda: phones.coverage(options.coverage_trials)
        ),
        rank_table=timed(seconds, "4. ranking", lambda: ranking.rank(rank_scenes)),
        facing_table=timed(seconds, "5. facing", lambda: facing.accuracy(n)),
        facing_coverage=timed(seconds, "6. facing coverage", lambda: facing.coverage(n)),
        six_point_rank=timed(seconds, "6. rank check", lambda: facing.six_point_rank(rank_scenes)),
        speed_result=timed(
            seconds, "7. speed", lambda: speed(options.speed_scenes, options.speed_rounds)
        ),
        limit_table=timed(seconds, "8. limit", lambda: limit.limit(options.limit_trials)),
        gravity_table=timed(seconds, "9. gravity", lambda: gravity.gravity(options.gravity_trials)),
        seconds=seconds,
    )


def main(argv: Sequence[str] | None = None) -> None:
    parser = command_line(__doc__, DEFAULT_OUT)
    defaults = Options()
    for name, meaning in (
        ("trials", "trials per cell (sections 1-2, 5-6)"),
        ("coverage_trials", "trials per case of the coverage table (default: 2x --trials)"),
        ("rank_scenes", "exact scenes per kind for the ranking checks"),
        ("speed_scenes", "scenes per timed case"),
        ("speed_rounds", "interleaved timing rounds"),
        ("limit_trials", "trials per case and tap noise (section 8)"),
        ("gravity_trials", "trials per case and gravity (section 9)"),
    ):
        default = None if name == "coverage_trials" else getattr(defaults, name)
        parser.add_argument(f"--{name.replace('_', '-')}", type=int, default=default, help=meaning)
    args = vars(parser.parse_args(argv))
    out = args.pop("out")
    if args["coverage_trials"] is None:
        args["coverage_trials"] = 2 * args["trials"]
    options = Options(**args)
    for name, value in args.items():
        if value < 1:
            parser.error(f"--{name.replace('_', '-')} must be at least 1")
    publish(report(run(options)), out)


if __name__ == "__main__":
    main()
