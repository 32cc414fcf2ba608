"""Whatever numbers arrive, ``solve`` answers with finite JSON or refuses with a code: never
another exception, never a NaN. Random taps over ten orders of magnitude, photo sizes from
a hundredth of a pixel to ten million, every way of marking the friends, every camera."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from shared_solver import SolverError, solve

CASES = 1500


def random_request(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, dict[str, object]]:
    n = int(rng.integers(1, 10))
    scale = 10.0 ** rng.uniform(-3, 8)
    p = rng.normal(size=(n, 2)) * scale
    q = p + rng.normal(size=(n, 2)) if rng.random() < 0.3 else rng.normal(size=(n, 2)) * scale
    marks: dict[str, object] = {}
    draw = rng.random()
    if draw < 0.5:
        marks["epipole1"] = rng.normal(size=2) * scale
        if rng.random() < 0.3:
            marks["epipole2"] = rng.normal(size=2) * scale
    elif draw < 0.65:
        marks["epipolar_line1"] = rng.normal(size=3)
    size = [float(10 ** rng.uniform(-2, 7)), float(10 ** rng.uniform(-2, 7))]
    kind = rng.choice(["phone", "unknown", "focal"])
    camera: object = (
        {"kind": "known_focal", "focal_35mm": float(10 ** rng.uniform(-2, 3.2))}
        if kind == "focal"
        else str(kind)
    )
    extra: dict[str, object] = {
        "image_size1": size,
        "image_size2": size[::-1],
        "camera1": camera,
        "camera2": "phone" if rng.random() < 0.7 else camera,
        "tap_sigma": float(10 ** rng.uniform(-2, 2)),
    }
    if rng.random() < 0.3:
        extra["points1_sigma"] = np.abs(rng.normal(size=n)) * 10 + 1e-3
    return p, q, marks | extra


def test_any_input_gets_finite_json_or_a_refusal() -> None:
    rng = np.random.default_rng(2026)
    answered = 0
    codes: list[str] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # overflow on the way to a refusal
        for _ in range(CASES):
            p, q, arguments = random_request(rng)
            try:
                result = solve(p, q, **arguments)  # type: ignore[arg-type]
            except SolverError as error:
                codes.append(error.code.value)
                continue
            text = json.dumps(result.model_dump(mode="json"), allow_nan=False)
            assert json.loads(text)["method"] == result.method
            answered += 1
    assert answered > 100
    assert len(codes) > 100
    assert all(codes)


@pytest.mark.parametrize(
    ("focal_35mm", "size"), [(5e-324, [100.0, 100.0]), (26.0, [1.7e308, 1.7e308])]
)
def test_a_focal_length_that_is_no_number_in_pixels_is_refused(
    focal_35mm: float, size: list[float]
) -> None:
    """A focal length that underflows to 0 px, or a photo whose diagonal overflows."""
    with pytest.raises(SolverError) as refused:
        solve(
            [[1.0, 2.0], [30.0, 40.0], [50.0, 7.0]],
            [[1.0, 2.0], [31.0, 50.0], [60.0, 7.0]],
            epipole1=[10.0, 25.0],
            image_size1=size,
            image_size2=[100.0, 100.0],
            camera1={"kind": "known_focal", "focal_35mm": focal_35mm},
            camera2="phone",
        )
    assert refused.value.code.value == "invalid_parameter"
