"""What is drawn of the answer, as shapes (shared_solver/drawing/layout.py), before any
renderer: the frame's size and outline, the curve's polylines, the border arrow. (The phone
once computed these itself; tests/e2e/test_one_drawing.py checks that both renderers draw
these shapes in the same place.)"""

from __future__ import annotations

import math

import numpy as np
import pytest

from shared_solver import SolveResult, solve
from shared_solver.drawing.layout import answer_drawing
from shared_solver.result import Ellipse, Uncertainty
from testbed.scenes import facing_scene

PHOTO = (640, 480)
PERSON = 800 / 55  # the photo's diagonal / 55


def answer(at: tuple[float, float], region: Ellipse | None) -> SolveResult:
    s = facing_scene(np.random.default_rng(2), 5)
    result = solve(
        s.landmarks1, s.landmarks2, epipole1=s.epipole1, image_size1=PHOTO, image_size2=PHOTO
    )
    return result.model_copy(update={"epipole2": at, "uncertainty": Uncertainty(ellipse=region)})


def region(a: float, b: float) -> Ellipse:
    return Ellipse(center=(300.0, 200.0), axes=(a, b), angle_deg=90.0)


def test_the_frame_is_never_smaller_than_a_person_and_says_friend_without_a_region() -> None:
    drawing = answer_drawing(answer((100.0, 100.0), None), photo=2, size=PHOTO)
    assert drawing.person == pytest.approx(PERSON)
    assert drawing.frame is not None
    assert drawing.frame.half == pytest.approx((PERSON, PERSON))
    assert (drawing.frame.sure, drawing.frame.label, drawing.frame.outline) == (
        False,
        "friend?",
        [],
    )
    assert drawing.focus is not None
    assert drawing.focus.half == pytest.approx((PERSON, PERSON))


@pytest.mark.parametrize(
    ("axes", "outlined"),
    [((3.0, 2.0), False), ((60.0, 3.0), False), ((60.0, 40.0), True), ((5000.0, 0.0), True)],
    ids=["smaller-than-a-person", "thin", "larger", "needle-across-the-photo"],
)
def test_the_region_is_outlined_when_it_leaves_the_person_clear_or_is_a_line(
    axes: tuple[float, float], outlined: bool
) -> None:
    drawing = answer_drawing(answer((300.0, 200.0), region(*axes)), photo=2, size=PHOTO)
    frame = drawing.frame
    assert frame is not None
    assert frame.sure
    assert bool(frame.outline) == outlined
    # The brackets hold the region (rotated 90 degrees: a along y), a little room around it.
    assert frame.half[1] >= min(axes[0], PHOTO[0] + PHOTO[1])
    assert frame.half[0] >= max(axes[1], PERSON)
    assert all(len(bracket) == 3 for bracket in frame.brackets)


def test_the_label_goes_below_the_frame_at_the_top_of_the_photo() -> None:
    top = answer_drawing(answer((300.0, 5.0), None), photo=2, size=PHOTO).frame
    middle = answer_drawing(answer((300.0, 240.0), None), photo=2, size=PHOTO).frame
    assert top is not None
    assert middle is not None
    assert not top.label_above
    assert middle.label_above
    assert middle.leader[1][1] < middle.leader[0][1] == pytest.approx(240.0 - PERSON)


def test_a_friend_off_the_photo_gets_an_arrow_from_the_centre_towards_them() -> None:
    drawing = answer_drawing(answer((1000.0, 240.0), None), photo=2, size=PHOTO)
    assert drawing.frame is None
    arrow = drawing.arrow
    assert arrow is not None
    assert arrow.direction == pytest.approx((1.0, 0.0))
    margin = math.hypot(*PHOTO) / 30
    assert arrow.tip == pytest.approx((PHOTO[0] - margin, 240.0))
    assert arrow.text == "friend 360 px off"
    assert drawing.focus is not None  # the phone still knows where to look


def test_the_curve_is_polylines_on_the_conic_inside_the_photo() -> None:
    # The circle (x - 320)^2 + (y - 240)^2 = 100^2.
    conic = ((1.0, 0.0, -320.0), (0.0, 1.0, -240.0), (-320.0, -240.0, 320.0**2 + 240.0**2 - 1e4))
    result = answer((0.0, 0.0), None).model_copy(
        update={"conic2": conic, "epipole2": None, "epipole2_h": None}
    )
    curve = answer_drawing(result, photo=2, size=PHOTO).curve
    assert curve is not None
    points = np.array([p for line in curve.polylines for p in line])
    assert len(points) > 8
    assert np.abs(np.hypot(points[:, 0] - 320, points[:, 1] - 240) - 100).max() < 0.3
    # Every stretch is drawn: consecutive vertices of the simplified pieces are close along
    # the circle, and the pieces together go all the way round.
    angles = np.sort(np.arctan2(points[:, 1] - 240, points[:, 0] - 320))
    gaps = np.diff(np.concatenate([angles, angles[:1] + 2 * math.pi]))
    assert gaps.max() < 0.5
