"""A phone's live view after its photo: the same hall, the phone turned where it stood.

:func:`live_views` renders a hall's photo as :mod:`testbed.venue` does (the stored size,
the phone's exposure, noise and JPEG), then frames of a live video from the same place:
the camera turned about a random axis, at a video stream's size and focal length (the
photo's scaled to the stream, times a zoom), its exposure changed, and a crowd of moving
figures pasted over it (filled ellipses of a person's proportions in random colours).
Everything about them is known: the turn and both cameras.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from shared_solver.projective import Array

from .hall import build_hall
from .phones import phone_scene
from .render import Surface, render
from .scenes import Camera
from .textures import Image
from .venue import photograph, stored_camera

# A phone's video stream, portrait (the photos are portrait too): 720 x 960 px.
VIDEO_SIZE = (720, 960)


@dataclass(frozen=True)
class Hall:
    """A rendered hall and its photo.

    Attributes:
        surfaces: what the hall is made of, to render more views.
        camera: the photo's camera (intrinsics at the stored size; its principal point is
            the phone's, near but not at the centre).
        photo: (H, W, 3) uint8 BGR, as the server stores it.
        other: the other phone's camera, at the hall's far end.
    """

    surfaces: list[Surface]
    camera: Camera
    photo: Image
    other: Camera


@dataclass(frozen=True)
class LiveView:
    """One frame of the live view and the truth about it.

    Attributes:
        frame: (h, w, 3) uint8 BGR.
        turn: (3, 3) R taking a direction in the photo's camera frame to the frame's.
        camera: the frame's camera (principal point at the centre).
    """

    frame: Image
    turn: Array
    camera: Camera


def rendered_hall(seed: int | Sequence[int]) -> Hall:
    """A hall around two phones (as :func:`testbed.venue.rendered_pair`) and phone 1's photo."""
    rng = np.random.default_rng(seed)
    phones = phone_scene(rng, 4)
    camera1, size1 = stored_camera(phones.camera1, phones.image_size1)
    camera2, _ = stored_camera(phones.camera2, phones.image_size2)
    surfaces = build_hall(rng, camera1, camera2)
    radiance, _ = render(surfaces, camera1, size1)
    return Hall(surfaces, camera1, photograph(rng, radiance), camera2)


def live_view(
    hall: Hall,
    rng: np.random.Generator,
    *,
    turn_deg: float,
    gain: float = 1.0,
    crowd: int = 0,
    zoom: float = 1.0,
    size: tuple[int, int] = VIDEO_SIZE,
    place: Camera | None = None,
    blur_px: int = 0,
    axis: Sequence[float] | None = None,
) -> LiveView:
    """A frame from the photo's place, the camera turned ``turn_deg`` about ``axis`` or a
    random one.

    Args:
        hall: the hall and its photo.
        rng: the turn's axis, the figures and the frame's noise.
        turn_deg: how far the phone has turned since the photo, degrees.
        gain: the frame's exposure against the photo's (0.5: half as bright).
        crowd: how many moving figures are pasted over the frame.
        zoom: the stream's focal length over the photo's scaled to the stream's size.
        size: (width, height) of the frame, px.
        place: the camera whose place and direction are turned (default: the photo's);
            another one's makes a frame of somewhere else.
        blur_px: a sideways motion blur this long (the phone turning as the frame is
            exposed), px.
        axis: (3,) the turn's axis in the photo's camera frame (x right, y down, z ahead),
            right-handed: (0, -1, 0) turns the phone to the right. Default: drawn from
            ``rng``.
    """
    about = rng.normal(size=3) if axis is None else np.asarray(axis, np.float64)
    turn = np.asarray(
        cv2.Rodrigues(about / np.linalg.norm(about) * math.radians(turn_deg))[0], np.float64
    )
    photo_size = hall.photo.shape[1], hall.photo.shape[0]
    focal = hall.camera.intrinsics[0, 0] * max(size) / max(photo_size) * zoom
    intrinsics = np.array([[focal, 0.0, size[0] / 2], [0.0, focal, size[1] / 2], [0.0, 0.0, 1.0]])
    start = hall.camera if place is None else place
    camera = Camera(intrinsics, turn @ start.rotation, turn @ start.translation)
    radiance, _ = render(hall.surfaces, camera, size)
    radiance = radiance * np.float32(gain)
    if blur_px > 1:
        kernel = np.full((1, blur_px), 1.0 / blur_px, np.float32)
        radiance = np.asarray(cv2.filter2D(radiance, -1, kernel), np.float32)
    frame = photograph(rng, radiance)
    for _ in range(crowd):
        width = int(rng.uniform(0.02, 0.06) * size[0])
        height = int(width * rng.uniform(2.0, 3.0))
        x, y = int(rng.uniform(0, size[0] - width)), int(rng.uniform(0, size[1] - height))
        colour = tuple(int(c) for c in rng.integers(0, 256, 3))
        centre, axes = (x + width // 2, y + height // 2), (width // 2, height // 2)
        cv2.ellipse(frame, centre, axes, 0.0, 0.0, 360.0, colour, -1)
    return LiveView(frame, turn, camera)


def marker_error_deg(hall: Hall, view: LiveView, rotation: Array) -> float:
    """The largest angle, degrees, between where a marker drawn with ``rotation`` points and
    where it should, over a 5 x 5 grid of the photo: each photo pixel's direction taken with
    the principal point at the photo's centre (all a phone knows), carried by ``rotation``,
    against its true direction in the frame's camera."""
    width, height = hall.photo.shape[1], hall.photo.shape[0]
    xs, ys = np.meshgrid(np.linspace(0.1, 0.9, 5) * width, np.linspace(0.1, 0.9, 5) * height)
    pixels = np.column_stack([xs.ravel(), ys.ravel(), np.ones(xs.size)])
    focal = hall.camera.intrinsics[0, 0]
    assumed = np.array([[focal, 0.0, width / 2], [0.0, focal, height / 2], [0.0, 0.0, 1.0]])
    truth = pixels @ np.linalg.inv(hall.camera.intrinsics).T @ view.turn.T
    drawn = pixels @ np.linalg.inv(assumed).T @ rotation.T
    truth /= np.linalg.norm(truth, axis=1, keepdims=True)
    drawn /= np.linalg.norm(drawn, axis=1, keepdims=True)
    cosines = np.clip(np.einsum("ij,ij->i", truth, drawn), -1.0, 1.0)
    return float(np.degrees(np.arccos(cosines)).max())
