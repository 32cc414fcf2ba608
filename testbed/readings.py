"""``solve`` on the test bed's phone scenes with both phones' gravity (and compass) readings
at the shutter: the readings drawn noisy, the cameras told, a refusal checked. Shared by the
solver's gravity and compass tests."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from shared_solver import SolverError, SolveResult, solve
from shared_solver.estimation.camera import focal_35mm
from testbed.phones import PhoneScene, gravity_reading, phone_scene

LEVEL = {"gravity1": [0.0, 1.0, 0.0], "gravity2": [0.0, 1.0, 0.0]}  # both phones upright


def down(scene: PhoneScene, photo: int, rng: np.random.Generator, sigma_deg: float) -> np.ndarray:
    return gravity_reading(scene.camera1 if photo == 1 else scene.camera2, sigma_deg, rng)


def true_cameras(scene: PhoneScene) -> tuple[dict[str, Any], dict[str, Any]]:
    """Each photo's true focal length as a known one (the scenes' centres are exact)."""
    return tuple(  # type: ignore[return-value]
        {"kind": "known_focal", "focal_35mm": focal_35mm(camera.intrinsics[0, 0], size)}
        for camera, size in ((scene.camera1, scene.image_size1), (scene.camera2, scene.image_size2))
    )


def exif_of(scene: PhoneScene) -> tuple[dict[str, Any], dict[str, Any]]:
    """Each photo's focal length as its EXIF says it (the true one, to a whole mm)."""
    return tuple(  # type: ignore[return-value]
        {"kind": "known_focal", "focal_35mm": focal}
        for focal in (scene.exif_focal_35mm1, scene.exif_focal_35mm2)
    )


def solved(
    scene: PhoneScene, landmarks: int, rng: np.random.Generator, **options: object
) -> SolveResult:
    sigma = float(options.pop("sigma", 0.0))  # type: ignore[arg-type]
    gravity_deg = float(options.pop("gravity_deg", 0.0))  # type: ignore[arg-type]
    cameras = options.pop("cameras", true_cameras(scene))
    measured = options.pop("measured", True)
    p = scene.landmarks1[:landmarks] + rng.normal(0.0, sigma, (landmarks, 2))
    q = scene.landmarks2[:landmarks] + rng.normal(0.0, sigma, (landmarks, 2))
    return solve(
        p,
        q,
        epipole1=scene.epipole1 + rng.normal(0.0, sigma, 2),
        tap_sigma=max(sigma, 1.0),
        **scene.sizes,
        camera1=cameras[0],  # type: ignore[index]
        camera2=cameras[1],  # type: ignore[index]
        gravity1=down(scene, 1, rng, gravity_deg) if measured else None,
        gravity2=down(scene, 2, rng, gravity_deg) if measured else None,
        gravity_sigma_deg=max(gravity_deg, 0.5),
        **options,  # type: ignore[arg-type]
    )


def phones_of(scene: PhoneScene) -> dict[str, Any]:
    """``solve``'s arguments besides the landmarks: friend 2's true mark, two phones."""
    return {
        "epipole1": scene.epipole1,
        **scene.sizes,
        "camera1": "phone",
        "camera2": "phone",
    }


def exact_scenes(count: int, landmarks: int = 1) -> list[PhoneScene]:
    rng = np.random.default_rng(40)
    return [phone_scene(rng, landmarks, centre_sd=0.0) for _ in range(count)]


def assert_refused(code: str, reason: str | None = None, **options: object) -> None:
    """No landmark on the first exact scene's two phones, with ``options``: refused with
    ``code`` (and ``reason``) and a sentence."""
    scene = exact_scenes(1)[0]
    with pytest.raises(SolverError) as refused:
        solve(np.zeros((0, 2)), np.zeros((0, 2)), **phones_of(scene), **options)  # type: ignore[arg-type]
    assert refused.value.code == code
    if reason is not None:
        assert refused.value.refusal.reason == reason
    assert refused.value.message
