"""Both photos resampled in epipolar coordinates around one landmark, where the two views of
a patch differ by little more than a stretch along the lines.

Rows are epipolar lines. Row ``j`` of photo A's patch is the line through the epipole
``e_A`` at angle ``theta_p + j / rho_p`` (rows 1 px apart at the tapped point ``p``, at
distance ``rho_p`` from ``e_A``); row ``j`` of photo B's strip is the line F maps it to,
through ``e_B``. Corresponding points lie on corresponding lines, so the rows of the two
views correspond exactly (Pollefeys, Koch & Van Gool, "A simple and efficient
rectification method for general motion", ICCV 1999, resample whole photos this way).

Columns run along the lines, 1 px apart. A surface that both cameras see from its front
reverses the order of its points along the lines: moving away from ``e_A`` in A is moving
towards ``e_B`` in B (in the epipolar plane, the angles at the two camera centres change
with opposite signs for any direction in a surface facing both). So A's patch is read
towards ``e_A`` and B's strip away from ``e_B``, and what is left between them is, to first
order, a stretch along the lines (the ratio of the surface's depths and slants) and a
shear (its tilt out of the epipolar plane): the search (:mod:`.search`) tries a few of
each. No rotation is left to search, whatever the two photos' orientations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from .. import linalg
from ..projective import Array
from .band import Band
from .epipolar import Epipolar

Image = NDArray[np.uint8]
_STATIONS = 9  # points along the band where its width is turned into rows


@dataclass(frozen=True)
class PolarFrame:
    """A landmark's patch in photo A and the means to read photo B's band around it.

    Attributes:
        patch: (2r + 1, 2r + 1[, 3]) photo A around the tapped point, rows along the
            epipolar lines, columns towards ``e_A`` (centre: the tapped point).
        origin: (2,) ``e_B`` in photo B, px.
        directions: (2 (r + m) + 1, 2) unit direction in B of each strip row's half-line.
        radius: r, the patch's half size, px.
        margin: m, extra rows on each side of a strip: how far (in rows) the true line may
            be from the answer's, anywhere along the band.
        photo: photo B.
        band: the landmark's band in B.
        step: angle (rad) between neighbouring rows in B.
    """

    patch: Image
    origin: Array
    directions: Array
    radius: int
    margin: int
    photo: Image
    band: Band
    step: float

    def reach(self, t: Array) -> Array:
        """(N,) rows on each side of the middle row the band covers at distances ``t``
        from ``e_B``, as far as the strip reaches (between 1 and ``margin``)."""
        return np.clip(self.across(t), 1, self.margin).astype(int)

    def across(self, t: Array) -> Array:
        """(N,) the band's half-width at distances ``t`` from ``e_B`` in rows, whole ones
        (its half-width over the rows' spacing there), however many the strip has."""
        middle = self.directions[len(self.directions) // 2]
        points = self.origin + t[:, None] * middle
        spacing = np.maximum(np.abs(t) * self.step, 1e-9)
        return np.ceil(self.band.half_width(points) / spacing)

    @property
    def rows(self) -> int:
        return len(self.directions)

    def strip(self, t: Array, shear: float = 0.0) -> Image:
        """(rows, len(t)[, 3]) photo B read along each row's half-line at distances ``t``
        (px from ``e_B``), each row shifted by ``shear`` px per row from the middle one."""
        offsets = shear * (np.arange(self.rows) - (self.rows - 1) / 2)
        along = t[None, :] + offsets[:, None]
        map_x = (self.origin[0] + along * self.directions[:, :1]).astype(np.float32)
        map_y = (self.origin[1] + along * self.directions[:, 1:]).astype(np.float32)
        return _image(
            cv2.remap(self.photo, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        )

    def point(self, row: float, t: float) -> Array:
        """(2,) the photo-B pixel of strip row ``row`` (0 = first) at distance ``t``."""
        low = min(max(math.floor(row), 0), self.rows - 1)
        high = min(low + 1, self.rows - 1)
        fraction = row - low
        direction = (1 - fraction) * self.directions[low] + fraction * self.directions[high]
        return self.origin + t * direction / linalg.norm(direction)


def polar_frame(
    photo_a: Image,
    photo_b: Image,
    point: Array,
    epipolar: Epipolar,
    band: Band,
    *,
    radius: int,
    max_margin: int,
) -> PolarFrame | None:
    """The frame of a landmark tapped at ``point`` (2,) in A, searched for in B.

    The strips have as many extra rows (the margin, at most ``max_margin``) as the band's
    half-width spans anywhere along it, so the search covers the band.

    None where epipolar coordinates do not exist: an epipole at infinity, or the point
    within two patch radii of ``e_A`` (there the lines through the patch fan out).
    """
    e_a, e_b = epipolar.epipole_a, epipolar.epipole_b
    if abs(e_a[2]) < 1e-12 * linalg.norm(e_a) or abs(e_b[2]) < 1e-12 * linalg.norm(e_b):
        return None
    centre_a, origin = e_a[:2] / e_a[2], e_b[:2] / e_b[2]
    offset = np.asarray(point, float) - centre_a
    rho = float(np.hypot(offset[0], offset[1]))
    if rho < 2 * radius:
        return None
    theta = math.atan2(offset[1], offset[0])

    def directions(steps: Array) -> Array:
        angles = theta + steps / rho
        return epipolar.direction(
            centre_a + rho * np.column_stack([np.cos(angles), np.sin(angles)])
        )

    # Rows one step apart in A are this far apart in angle in B.
    neighbours = directions(np.array([-1.0, 1.0]))
    step = math.acos(float(np.clip(neighbours[0] @ neighbours[1], -1.0, 1.0))) / 2
    stations = band.along(_STATIONS)
    t = (stations - origin) @ directions(np.zeros(1))[0]
    spacing = np.maximum(np.abs(t) * step, 1e-9)
    margin = int(np.clip(np.ceil(band.half_width(stations) / spacing).max(), 1, max_margin))
    steps = np.arange(-radius - margin, radius + margin + 1, dtype=float)
    angles = theta + steps[margin : margin + 2 * radius + 1] / rho
    middle = np.column_stack([np.cos(angles), np.sin(angles)])
    # The patch: read towards e_A, from distance rho + r down to rho - r.
    distances = rho + np.arange(radius, -radius - 1, -1, dtype=float)
    map_x = (centre_a[0] + distances[None, :] * middle[:, :1]).astype(np.float32)
    map_y = (centre_a[1] + distances[None, :] * middle[:, 1:]).astype(np.float32)
    patch = _image(
        cv2.remap(photo_a, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    )
    return PolarFrame(patch, origin, directions(steps), radius, margin, photo_b, band, step)


def _image(pixels: NDArray[np.generic]) -> Image:
    """OpenCV's result typed as the uint8 image it is (no copy)."""
    return np.asarray(pixels, dtype=np.uint8)
