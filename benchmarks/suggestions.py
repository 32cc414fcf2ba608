"""Buddy Search suggestion benchmark: bands, suggestions and tap checks on rendered halls.

Two friends photograph a hall from its two ends (``testbed.venue``: textured planes
rendered by homography, the stored 2560 px photos, every landmark's true position known).
Friend 1 marks friend 2 and both tap 5 landmarks with 3 px of noise; ``solve`` answers
with phone cameras. Then, for other landmarks tapped in one photo only (up to 4 per kind
of surface per scene, in both directions), it measures:

1. the scenes;
2. the band: how often the true landmark is inside its 95 % band (answers from 3, 5 and
   8 landmarks), how wide the band is;
3. the suggestions under the rule in the code (``shared_solver.matching.suggestion.RULES``):
   the fraction of landmarks that get one, the fraction of those within 1 % of the
   diagonal of the truth (target: at least 90 %), per kind of surface; and suggestions
   for spots the other photo does not show (all wrong);
4. the rule: thresholds tried on other scenes (the calibration stream), the chosen one;
5. the method against SIFT keypoints matched in the band, and against grey photos;
6. the tap check: right taps flagged, wrong ones (another landmark's spot, the truth moved
   2-10 % of the diagonal) flagged;
7. the time of ``suggest`` per landmark.

Scenes are seeded (SEED, stream, index): scene i is the same whatever the counts. Run from
the repository root:

    .venv/bin/python benchmarks/suggestions.py [--calibration N] [--evaluation N]
        [--compare N] [--out PATH]                                   (``make bench-suggest``)

The report is printed and written as Markdown to ``docs/suggestions.md``.
"""

from __future__ import annotations

import argparse
import os
import platform
import shlex
import sys
from collections.abc import Sequence
from datetime import datetime
from pathlib import Path

import cv2
import numpy as np
from report import ROOT, publish, source_state, timed
from suggestbench import tables
from suggestbench.trials import ABSENT, PER_KIND, SEED, SIGMA, STREAMS, USED, SceneRun, run_scene

from shared_solver.matching import FLAG_SIGMAS, LEVEL, RULES

DEFAULT_OUT = ROOT / "docs" / "suggestions.md"
DEFAULT_CALIBRATION = 30
DEFAULT_EVALUATION = 40
DEFAULT_COMPARE = 10


def header(arguments: argparse.Namespace) -> str:
    now = datetime.now().astimezone().isoformat(timespec="seconds")
    return "\n".join(
        [
            "# Suggestion benchmark",
            "",
            f"Command: `{shlex.join(['python', 'benchmarks/suggestions.py', *sys.argv[1:]])}` "
            "(from the repository root, in its virtualenv; `make bench-suggest`)",
            "",
            f"- Date: {now}",
            f"- Machine: {platform.platform()}, {platform.machine()}, "
            f"os.cpu_count() = {os.cpu_count()}, OpenCV threads {cv2.getNumThreads()}",
            f"- Python {platform.python_version()}, numpy {np.__version__}, "
            f"OpenCV {cv2.__version__}",
            f"- shared_solver and testbed: {source_state('shared_solver', 'testbed')}",
            f"- Scenes: `testbed.venue.rendered_pair((SEED={SEED}, stream, index))`, streams "
            f"{STREAMS}: {arguments.calibration} calibration scenes (section 4), "
            f"{arguments.evaluation} evaluation scenes (sections 1-3, 6, 7), the first "
            f"{arguments.compare} of them also in section 5. Taps: numpy "
            "`default_rng((SEED, stream, index, 1))`.",
            f"- The answer: friend 2 and {USED} landmarks at random, every tap with Gaussian "
            f"noise of {SIGMA:g} px per axis, `solve(..., tap_sigma={SIGMA:g}, "
            'camera1="phone", camera2="phone", fundamental_covariance=True)`. Searched: up to '
            f"{PER_KIND} other landmarks per kind of surface per scene, tapped with the same "
            f"noise, each looked for in the other photo in both directions; up to {ABSENT} "
            "spots per photo that the other does not show.",
            f"- The rule: `{RULES}`; band at {100 * LEVEL:.0f} %; a tap is flagged beyond "
            f"{FLAG_SIGMAS:g} standard deviations.",
        ]
    )


def report(runs: Sequence[SceneRun], arguments: argparse.Namespace, seconds: float) -> str:
    evaluation = [run for run in runs if run.stream == "evaluation" and run.answered]
    calibration = [run for run in runs if run.stream == "calibration" and run.answered]
    searched = [item for run in evaluation for item in run.searched]
    absent = [item for run in evaluation for item in run.absent]
    headline, result = tables.headline(searched, absent)
    sift_seconds = [value for run in evaluation for value in run.sift_seconds]
    times = [item.colour.seconds for item in searched if item.colour is not None]
    times += [item.colour.seconds for item in absent if item.colour is not None]
    passed = result.shown > 0 and result.precision >= tables.TARGET_PRECISION
    median_ms = 1000 * float(np.median(times)) if times else float("nan")
    sections = [
        header(arguments),
        "## 1. The rendered halls",
        "Each scene: two phones placed as `testbed.phones.phone_scene` places them (12 MP, "
        "26 mm, 20-80 m apart, each aimed by hand at the other, photos downscaled to 2560 px "
        "as the server stores them), a hall built around them (`testbed.hall`: court floor, "
        "side and end stands with seated people, walls with posters, advertising boards, "
        "roof, pillars, equipment on the floor, a stage, a hanging scoreboard; textures "
        "drawn with OpenCV and noise), each photo rendered by homography per plane with a "
        "depth buffer and mip levels, then exposure, white balance, vignetting, blur, noise "
        "and JPEG at the server's quality 90. Landmarks are salient spots (corners of "
        "posters, signs, boards, boxes, floor lines) both photos show unoccluded. A scene is "
        f"used when it has at least {USED + 2} landmarks and `solve` claims an uncertainty "
        "of F.",
        tables.scenes_table(runs),
        "## 2. The band",
        f"The true landmark inside its {100 * LEVEL:.0f} % band (evaluation scenes; the "
        f"answer from {USED} landmarks is the one searched below, the others are answers "
        "from the first 3 or 8 of the same shuffled landmarks, checked on the rest). "
        "Within the flag's limit: the fraction of right taps of a perfect finger that would "
        "not be flagged.",
        tables.band_table(evaluation),
        tables.band_sizes(searched),
        "## 3. Suggestions",
        "Evaluation scenes, the rule in the code. A suggestion is right within 1 % of the "
        "photo's diagonal (32 px at 2560 x 1920) of the true landmark.",
        headline,
        "By kind of surface (*best match within 1 %*: the search's best place, whether the "
        "rule shows it or not):",
        tables.kinds_table(searched),
        "## 4. Choosing the rule",
        f"Calibration scenes ({len(calibration)} answered, none of them in the evaluation): "
        "share of landmarks shown / share of those within 1 %, for each least score and "
        "least margin over the runner-up, with the search back; the last column without "
        "it. In bold, the rule in the code.",
        tables.rule_table([item for run in calibration for item in run.searched]),
        "## 5. Against SIFT in the band, and without colour",
        f"The first {arguments.compare} evaluation scenes, the same landmarks and taps. "
        "SIFT: `benchmarks/suggestbench/sift.py` (keypoints of A within 48 px of the tap, "
        "each matched to B's keypoints inside its own band with Lowe's ratio 0.8; the "
        "prediction most matches agree with). Grey: the same search on the photos "
        "converted to grey.",
        tables.methods_table(searched, sift_seconds),
        "## 6. The tap check",
        "Each searched landmark tapped in the other photo three ways, checked against its "
        "band: right (the truth with 3 px of noise), another searched landmark's spot, and "
        "the truth moved 2-10 % of the diagonal in a random direction (a mis-tap along the "
        "band cannot be told from a right one: those count as not flagged).",
        tables.flags_table(searched),
        "## 7. Time",
        "What `suggest` spends per landmark (evaluation scenes, spots of one photo "
        "included): the search along the band, and the search back for a match that "
        "leads. One process on this machine, which other work shares; the band alone is a "
        "few small matrix products.",
        tables.time_table(searched, absent),
        "## Targets",
        "\n".join(
            [
                f"- {'PASS' if passed else 'FAIL'}: at least "
                f"{100 * tables.TARGET_PRECISION:.0f} % of shown suggestions within 1 % of the "
                f"diagonal: {result.right} of {result.shown} ({tables.share(result.precision)}).",
                f"- REPORTED: landmarks that get a suggestion: {result.shown} of "
                f"{result.searched} ({tables.share(result.coverage)}).",
                "- REPORTED (a few tens of ms would be good): `suggest` takes "
                f"{median_ms:.0f} ms per call (median, section 7).",
            ]
        ),
        f"Wall time of the run: {seconds:.0f} s.",
    ]
    return "\n\n".join(sections) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--calibration", type=int, default=DEFAULT_CALIBRATION)
    parser.add_argument("--evaluation", type=int, default=DEFAULT_EVALUATION)
    parser.add_argument("--compare", type=int, default=DEFAULT_COMPARE)
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT)
    arguments = parser.parse_args()
    seconds: dict[str, float] = {}

    def everything() -> list[SceneRun]:
        runs = [run_scene("calibration", i) for i in range(arguments.calibration)]
        runs += [
            run_scene("evaluation", i, compare=i < arguments.compare)
            for i in range(arguments.evaluation)
        ]
        return runs

    runs = timed(seconds, "scenes", everything)
    publish(report(runs, arguments, seconds["scenes"]), arguments.out)


if __name__ == "__main__":
    main()
