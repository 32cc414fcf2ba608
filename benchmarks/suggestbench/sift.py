"""The alternative to template matching: SIFT keypoints matched inside the band.

Guided matching (Hartley & Zisserman 11.9): photo B's SIFT keypoints are computed once
per photo (a server could keep them with the photo), those of photo A in a window around
the tapped point. Each keypoint of the window may only match a keypoint of B within the
band of its own epipolar line, the nearest descriptor passing Lowe's ratio test. Each
match predicts where the tapped point is in B (the keypoints' scale and orientation give
the similarity between them); the prediction most others agree with (within 1 % of the
diagonal) is the suggestion, its support the number agreeing. (OpenCV 5 keeps AKAZE in the
contrib modules, which the project does not install; SIFT is in the main one.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from shared_solver.matching import Epipolar
from shared_solver.matching.band import Band
from shared_solver.projective import Array

WINDOW = 48  # px around the tapped point whose keypoints are matched
RATIO = 0.8  # Lowe's ratio test
SLACK = 3.0  # px added to the band's half-width for a keypoint's own band


@dataclass(frozen=True)
class Features:
    """A photo's SIFT keypoints: (N, 2) positions, (N,) sizes and angles (rad, clockwise
    in the photo's x right, y down frame), (N, 128) descriptors."""

    points: Array
    sizes: Array
    angles: Array
    descriptors: Array

    @classmethod
    def of(cls, photo: np.ndarray) -> Features:
        grey = cv2.cvtColor(photo, cv2.COLOR_BGR2GRAY)
        keypoints, descriptors = cv2.SIFT.create().detectAndCompute(grey, None)
        return cls(
            np.array([k.pt for k in keypoints]).reshape(-1, 2),
            np.array([k.size for k in keypoints]),
            np.radians([k.angle for k in keypoints]),
            np.zeros((0, 128)) if descriptors is None else descriptors.astype(np.float32),
        )


def sift_match(
    features_a: Features, features_b: Features, point: Array, epipolar: Epipolar, band: Band
) -> tuple[Array | None, int]:
    """(predicted point in B or None, its support) for the landmark tapped at ``point``."""
    near = np.flatnonzero(np.hypot(*(features_a.points - point).T) <= WINDOW)
    if len(near) == 0 or len(features_b.points) < 2:
        return None, 0
    lifted_b = np.column_stack([features_b.points, np.ones(len(features_b.points))])
    tolerance = band.half_width(features_b.points) + SLACK
    predictions = []
    for k in near:
        line = epipolar.fundamental @ np.append(features_a.points[k], 1.0)
        line /= math.hypot(line[0], line[1])
        candidates = np.flatnonzero(np.abs(lifted_b @ line) <= tolerance)
        if len(candidates) == 0:
            continue
        distances = np.linalg.norm(
            features_b.descriptors[candidates] - features_a.descriptors[k], axis=1
        )
        order = np.argsort(distances)
        if len(order) > 1 and distances[order[0]] > RATIO * distances[order[1]]:
            continue
        j = candidates[order[0]]
        scale = features_b.sizes[j] / features_a.sizes[k]
        turn = features_b.angles[j] - features_a.angles[k]
        rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
        predictions.append(features_b.points[j] + scale * rotation @ (point - features_a.points[k]))
    if not predictions:
        return None, 0
    stacked = np.array(predictions)
    size_b = band.size
    agree = 0.01 * math.hypot(*size_b)
    support = [(np.hypot(*(stacked - p).T) <= agree).sum() for p in stacked]
    best = int(np.argmax(support))
    cluster = stacked[np.hypot(*(stacked - stacked[best]).T) <= agree]
    return np.median(cluster, axis=0), int(support[best])
