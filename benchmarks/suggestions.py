"""Buddy Search suggestion benchmark: bands, suggestions and tap checks on rendered venues.

Two friends photograph a venue from its two ends (``testbed.venue``: textured planes
rendered by homography, the stored 2560 px photos, every landmark's true position known):
the suite's halls, and arenas full of look-alikes (banners seen from both sides, mats,
signs and posters alike, pillars alike, a video board, moving spotlights). It measures:

1. the scenes;
2. the band (halls): how often the true landmark is inside its 95 % band (answers from
   3, 5 and 8 landmarks), how wide the band is;
3. the suggestions in the halls under the rule in the code
   (``shared_solver.matching.suggestion.RULES``): friend 1 marks friend 2, both tap 5
   landmarks with 3 px of noise; other landmarks (up to 4 per kind of surface per scene),
   tapped in one photo, are looked for in the other, both ways; and spots the other photo
   does not show (any suggestion there is wrong);
4. the suggestions in the arenas, held out (:mod:`suggestbench.arenas`): 10 landmarks a
   person would pick, 3 or 5 of them found, the rest asked for, taps with 1, 3 or 8 px of
   noise; the targets: of the spots offered, at least 95 % within 1 % of the diagonal and
   none beyond 3 %, with at least 25 % of landmarks offered one; the same landmarks
   searched as before;
5. the rule: thresholds tried on other scenes (the calibration halls and arenas);
6. the method against SIFT keypoints matched in the band, and against grey photos (halls);
7. the tap check (halls): right taps flagged, wrong ones (another landmark's spot, the
   truth moved 2-10 % of the diagonal) flagged;
8. the time of ``suggest`` per landmark.

Scenes are seeded (SEED, stream, index): scene i is the same whatever the counts. Run from
the repository root:

    .venv/bin/python benchmarks/suggestions.py [--calibration N] [--evaluation N]
        [--compare N] [--arena-calibration N] [--arena-evaluation N] [--out PATH]
                                                                     (``make bench-suggest``)

The report is printed and written as Markdown to ``docs/suggestions.md``.
"""

from __future__ import annotations

import argparse
import platform
from collections.abc import Sequence

import cv2
import numpy as np
from report import ROOT, command_line, heading, machine, publish, source_state, timed
from suggestbench import arena_tables, tables
from suggestbench.arenas import ARENA_STREAMS, PICKED, ArenaRun, run_arena
from suggestbench.trials import ABSENT, PER_KIND, SEED, SIGMA, STREAMS, USED, SceneRun, run_scene

from shared_solver.matching import FLAG_SIGMAS, LEVEL, RULES

DEFAULT_OUT = ROOT / "docs" / "suggestions.md"
DEFAULT_CALIBRATION = 16
DEFAULT_EVALUATION = 24
DEFAULT_COMPARE = 8
DEFAULT_ARENA_CALIBRATION = 12
DEFAULT_ARENA_EVALUATION = 20


def header(arguments: argparse.Namespace) -> str:
    return "\n".join(
        [
            *heading("Suggestion benchmark", "benchmarks/suggestions.py", "bench-suggest"),
            machine(f", OpenCV threads {cv2.getNumThreads()}"),
            f"- Python {platform.python_version()}, numpy {np.__version__}, "
            f"OpenCV {cv2.__version__}",
            f"- shared_solver and testbed: {source_state('shared_solver', 'testbed')}",
            f"- Halls: `testbed.venue.rendered_pair((SEED={SEED}, stream, index))`, streams "
            f"{STREAMS}: {arguments.calibration} calibration halls (section 5), "
            f"{arguments.evaluation} evaluation halls (sections 1-3, 7, 8), the first "
            f"{arguments.compare} of them also in section 6. Taps: numpy "
            "`default_rng((SEED, stream, index, 1))`.",
            f"- In the halls, the answer: friend 2 and {USED} landmarks at random, every tap "
            f"with Gaussian noise of {SIGMA:g} px per axis, `solve(..., tap_sigma={SIGMA:g}, "
            'camera1="phone", camera2="phone", fundamental_covariance=True)`. Searched: up to '
            f"{PER_KIND} other landmarks per kind of surface per scene, tapped with the same "
            f"noise, each looked for in the other photo in both directions; up to {ABSENT} "
            "spots per photo that the other does not show.",
            f"- Arenas: `testbed.venue.rendered_arena((SEED={SEED}, stream, index))`, streams "
            f"{ARENA_STREAMS}: {arguments.arena_calibration} calibration arenas (section 5), "
            f"{arguments.arena_evaluation} evaluation arenas (sections 1, 4, 8), held out "
            "from every choice of the rule (streams 4 to 8 were looked at for choices). "
            "Taps: numpy `default_rng((SEED, stream, index, 1))`.",
            f"- The rule: `{RULES}`; band at {100 * LEVEL:.0f} %; a tap is flagged beyond "
            f"{FLAG_SIGMAS:g} standard deviations.",
        ]
    )


HALLS = (
    "Each hall: two phones placed as `testbed.phones.phone_scene` places them (12 MP, "
    "26 mm, 20-80 m apart, each aimed by hand at the other, photos downscaled to 2560 px "
    "as the server stores them), a hall built around them (`testbed.hall`: court floor, "
    "side and end stands with seated people, walls with posters, advertising boards, "
    "roof, pillars, equipment on the floor, a stage, a hanging scoreboard; textures "
    "drawn with OpenCV and noise), each photo rendered by homography per plane with a "
    "depth buffer and mip levels, then exposure, white balance, vignetting, blur, noise "
    "and JPEG at the server's quality 90. Landmarks are salient spots (corners of "
    "posters, signs, boards, boxes, floor lines) both photos show unoccluded. A hall is "
    f"used when it has at least {USED + 2} landmarks and `solve` claims an uncertainty "
    "of F."
)
ARENAS = (
    "Each arena (`testbed.arena`): a hall as above, and in it banners hung across the "
    "hall above the phones, one phone seeing their front and the other their back (mesh "
    "banners whose print shows through, mirrored from behind, and banners printed to read "
    "from both sides; a sponsor has several alike), signs alike along the sides and hung "
    "across (printed on both sides), rows of posters alike, mats alike on the floor (each "
    "print the same turned 180 degrees), pillars alike, a video board showing something "
    "else in each photo, and spotlights whose pools of light move between the two photos. "
    f"A person picks {PICKED} landmarks both photos show, one kind of thing at a time, "
    "at least 3 % of the diagonal apart; an arena is used when it has that many."
)


def report(
    runs: Sequence[SceneRun],
    arenas: Sequence[ArenaRun],
    arguments: argparse.Namespace,
    seconds: float,
) -> str:
    evaluation = [run for run in runs if run.stream == "evaluation" and run.answered]
    calibration = [run for run in runs if run.stream == "calibration" and run.answered]
    searched = [item for run in evaluation for item in run.searched]
    absent = [item for run in evaluation for item in run.absent]
    asked = [item for run in arenas if run.stream == "evaluation" for item in run.asked]
    tuning = [item for run in arenas if run.stream == "calibration" for item in run.asked]
    tuning_halls = [item for run in calibration for item in run.searched]
    headline, result = tables.headline(searched, absent)
    offered, total = arena_tables.offered_table(asked)
    sift_seconds = [value for run in evaluation for value in run.sift_seconds]
    timed = [item.colour for item in searched if item.colour is not None]
    timed += [item.colour for item in absent if item.colour is not None]
    timed += [item.timed for item in asked if item.timed is not None]
    times = [t.seconds for t in timed]
    passed = result.offered > 0 and result.precision >= tables.TARGET_PRECISION
    median_ms = 1000 * float(np.median(times)) if times else float("nan")
    sections = [
        header(arguments),
        "## 1. The rendered venues",
        HALLS,
        tables.scenes_table(runs),
        ARENAS,
        arena_tables.scenes_table(arenas),
        "## 2. The band",
        f"The true landmark inside its {100 * LEVEL:.0f} % band (evaluation halls; the "
        f"answer from {USED} landmarks is the one searched below, the others are answers "
        "from the first 3 or 8 of the same shuffled landmarks, checked on the rest). "
        "Within the flag's limit: the fraction of right taps of a perfect finger that would "
        "not be flagged.",
        tables.band_table(evaluation),
        tables.band_sizes(searched),
        "## 3. Suggestions in the halls",
        "Evaluation halls, the rule in the code. A suggestion is right within 1 % of the "
        "photo's diagonal (32 px at 2560 x 1920) of the true landmark.",
        headline,
        "By kind of surface (*best match within 1 %*: the search's best place, whether the "
        "rule shows it or not):",
        tables.kinds_table(searched),
        "## 4. Suggestions in the arenas, held out",
        f"Evaluation arenas ({len({a.scene for a in asked})} used), none of them seen while "
        "the rule was chosen. In each, friend 1 marks friend 2 and both tap the first 3 (or "
        "5) of the picked landmarks; `solve` answers with phone cameras and the taps' "
        "noise as `tap_sigma`; each other landmark, tapped in one photo, is asked for in "
        "the other, both ways. Every tap has Gaussian noise of the given sd per axis (one "
        "draw per arena and noise). *Worst*: the farthest offered spot from the truth, "
        "fraction of the diagonal.",
        offered,
        "By kind of thing (*best place*: the search's, whether the rule offers it or not):",
        arena_tables.kinds_table(asked),
        "The same landmarks and taps, searched as before this change (the patch as read "
        "alone) and decided by the rule before (score 0.7, lead 0.05 over the runner-up, "
        "the search back landing within 1 % of the tap, however unsurely), and by the rule "
        "in the code but where the band is wider than `max_across` too (the rule before "
        "that limit) or without the context:",
        arena_tables.before_table(asked),
        "What a stricter rule would give on the same held-out arenas (shown, not chosen "
        "from: the rule was fixed before this run):",
        arena_tables.tradeoff_table(asked),
        "## 5. Choosing the rule",
        f"Calibration halls ({len(calibration)} answered) and arenas "
        f"({len({a.scene for a in tuning})} used), none of them in the evaluation: share of "
        "landmarks offered a spot / share of those within 1 % / how many beyond 3 %, for "
        "each least score and least lead over the runner-up (the search back held to the "
        "same). In bold, the rule in the code. Arenas:",
        arena_tables.rule_table(tuning),
        "Halls:",
        arena_tables.rule_table(tuning_halls),
        "A match in another view than as read (a banner seen from behind, a look-alike "
        "read the other way): offered / right / beyond 3 % for each least lead over the "
        "best place of the patch as read, the rest as in the code. Arenas:",
        arena_tables.view_table(tuning),
        "Halls:",
        arena_tables.view_table(tuning_halls),
        "The context (a patch twice the size, matched where each place was found): "
        "offered / right / beyond 3 % for each least score of the match in its context and "
        "each least lead of its context over every other place's, which stands in for the "
        "least lead over the runner-up (here and on the search back), the rest as in the "
        "code. The thresholds were chosen on the arenas of seed stream 7 and checked on "
        "stream 8 (neither here nor held out). Arenas:",
        arena_tables.context_table(tuning),
        "Halls:",
        arena_tables.context_table(tuning_halls),
        "## 6. Against SIFT in the band, and without colour",
        f"The first {arguments.compare} evaluation halls, the same landmarks and taps. "
        "SIFT: `benchmarks/suggestbench/sift.py` (keypoints of A within 48 px of the tap, "
        "each matched to B's keypoints inside its own band with Lowe's ratio 0.8; the "
        "prediction most matches agree with). Grey: the same search on the photos "
        "converted to grey.",
        tables.methods_table(searched, sift_seconds),
        "## 7. The tap check",
        "Each searched landmark tapped in the other photo three ways, checked against its "
        "band: right (the truth with 3 px of noise), another searched landmark's spot, and "
        "the truth moved 2-10 % of the diagonal in a random direction (a mis-tap along the "
        "band cannot be told from a right one: those count as not flagged). A suggested "
        "spot taken with one tap is checked the same way.",
        tables.flags_table(searched),
        "## 8. Time",
        "What `suggest` spends per landmark (evaluation halls, spots of one photo "
        "included, and evaluation arenas): the search along the band, and the search back "
        "for a match that leads. One process on this machine, which other work shares; the "
        "band alone is a few small matrix products.",
        tables.time_table(timed),
        "## Targets",
        "Arenas, held out (section 4), over every tap noise:",
        "\n".join(arena_tables.targets(total, asked)),
        "Halls (section 3) and time:",
        "\n".join(
            [
                f"- {'PASS' if passed else 'FAIL'}: at least "
                f"{100 * tables.TARGET_PRECISION:.0f} % of shown suggestions within 1 % of the "
                f"diagonal: {result.right} of {result.offered} ({tables.share(result.precision)}).",
                f"- REPORTED: landmarks that get a suggestion: {result.offered} of "
                f"{result.asked} ({tables.share(result.coverage)}).",
                "- REPORTED (a few tens of ms would be good): `suggest` takes "
                f"{median_ms:.0f} ms per call (median, section 8).",
            ]
        ),
        f"Wall time of the run: {seconds:.0f} s.",
    ]
    return "\n\n".join(sections) + "\n"


def main() -> None:
    parser = command_line(__doc__, DEFAULT_OUT)
    parser.add_argument("--calibration", type=int, default=DEFAULT_CALIBRATION)
    parser.add_argument("--evaluation", type=int, default=DEFAULT_EVALUATION)
    parser.add_argument("--compare", type=int, default=DEFAULT_COMPARE)
    parser.add_argument("--arena-calibration", type=int, default=DEFAULT_ARENA_CALIBRATION)
    parser.add_argument("--arena-evaluation", type=int, default=DEFAULT_ARENA_EVALUATION)
    arguments = parser.parse_args()
    seconds: dict[str, float] = {}

    def halls() -> list[SceneRun]:
        runs = [run_scene("calibration", i) for i in range(arguments.calibration)]
        runs += [
            run_scene("evaluation", i, compare=i < arguments.compare)
            for i in range(arguments.evaluation)
        ]
        return runs

    def arenas() -> list[ArenaRun]:
        runs = [
            run_arena("calibration", i, always_back=True)
            for i in range(arguments.arena_calibration)
        ]
        runs += [
            run_arena("evaluation", i, always_back=False, compare=True)
            for i in range(arguments.arena_evaluation)
        ]
        return runs

    runs = timed(seconds, "halls", halls)
    arena_runs = timed(seconds, "arenas", arenas)
    publish(report(runs, arena_runs, arguments, sum(seconds.values())), arguments.out)


if __name__ == "__main__":
    main()
