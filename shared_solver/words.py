"""Every sentence the solver says to a person: warnings on an answer and reasons for a refusal.

They reach a phone's screen, so they are written for the two friends: "your friend", "the
friend mark", "landmark #3", and a next step to take. A refusal names photos "photo 1" and
"photo 2" and nothing else, so that a session can say them to each phone as "your photo" and
"your friend's photo". A warning names none by number ("this photo" is said only to the
phone whose photo it is), so one sentence serves both phones; which phone is told it is the
photo it is about (``errors.WARNING_PHOTO``), not its wording (:func:`warning`). Kept in
one place so the voice stays one, and so a change of wording never hides in the geometry.
"""

from __future__ import annotations

from typing import Literal, TypeVar

from .errors import WarningCode

Side = Literal["left", "right", "up", "down"]
_T = TypeVar("_T")

# --- warnings on an answer -----------------------------------------------------------------

CAMERA_MODEL_DISAGREES = (
    "These marks do not fit two ordinary phone photos (a cropped or edited photo, or a "
    "mis-tapped landmark), so the answer does not assume the camera's shape."
)
CAMERA_MODEL_UNSURE = (
    "These marks do not quite fit two ordinary phone photos (a cropped or edited photo, or a "
    "mis-tapped landmark): the frame is widened to hold your friend either way. Add landmarks "
    "to narrow it down."
)
ON_THE_CURVE = (
    "Your friend is somewhere on the curve. Mark one more landmark in both photos to pin "
    "down the spot."
)
MARKS_DISAGREE = (
    "The marks disagree more than tapping error explains: re-check the friend mark and each "
    "landmark (same spot, same number in both photos). The uncertainty is widened."
)
FAR_TO_THE_SIDE = (
    "The landmarks put your friend very far off to the side; re-check the marks or add landmarks."
)
NOT_PINNED_DOWN = (
    "These marks do not pin down where your friend is; re-check each landmark and the friend "
    "mark, or add landmarks."
)
BEHIND_YOU = "Your friend is behind you: turn around, and photograph the side where they are."
UNCERTAIN = (
    "The position is uncertain. Add landmarks spread across both photos, near and far, to "
    "narrow it down."
)
_TURN: dict[Side, str] = {
    "left": "turn left",
    "right": "turn right",
    "up": "look up",
    "down": "look down",
}


def mistapped(label: int, off_px: float) -> str:
    """A landmark left out of the answer because it does not fit the others."""
    return (
        f"Landmark #{label} looks mis-tapped (about {off_px:.0f} px from where the others put "
        f"it), so the answer leaves it out. Re-check #{label} in both photos."
    )


def misfit(label: int) -> str:
    """A landmark tapped far from where the others put it (outside its band)."""
    return f"#{label} does not fit the others: check it in both photos."


def outside_photo(beyond_px: float, side: Side) -> str:
    """The friend is beyond one edge of the photo."""
    return (
        f"Your friend is outside this photo, about {beyond_px:.0f} px beyond its {side} edge: "
        f"{_TURN[side]}."
    )


Marked = Literal["point", "line", "none"]  # how the friend was marked in photo 1


def ambiguous(*, marked: Marked) -> str:
    """Several geometries fit the landmarks equally well."""
    return (
        "More than one position fits these landmarks; the likeliest is marked and the others "
        f"are listed. To decide, {_decide(marked)}."
    )


def no_margin(*, marked: Marked) -> str:
    """An answer ranked first among several, with no region claimed."""
    return f"This position has no reliable error margin; to get one, {_decide(marked)}."


def _decide(marked: Marked) -> str:
    return {
        "point": "add a landmark",
        "line": "tap your friend instead of a line, or add a landmark",
        "none": "tap your friend if you can see them, or add a landmark",
    }[marked]


_FIXED: dict[WarningCode, str] = {
    WarningCode.CAMERA_MODEL_DISAGREES: CAMERA_MODEL_DISAGREES,
    WarningCode.CAMERA_MODEL_UNSURE: CAMERA_MODEL_UNSURE,
    WarningCode.ON_THE_CURVE: ON_THE_CURVE,
    WarningCode.MARKS_DISAGREE: MARKS_DISAGREE,
    WarningCode.FAR_TO_THE_SIDE: FAR_TO_THE_SIDE,
    WarningCode.NOT_PINNED_DOWN: NOT_PINNED_DOWN,
    WarningCode.BEHIND_YOU: BEHIND_YOU,
    WarningCode.UNCERTAIN: UNCERTAIN,
}


def warning(
    code: WarningCode,
    *,
    landmark: int | None = None,
    distance_px: float | None = None,
    side: Side | None = None,
    marked: Marked | None = None,
) -> str:
    """A warning's sentence, from its code and its parameters: the one wording of each code
    (``shared_solver.result.SolverWarning`` carries all three). Which phone is told it is
    the warning's ``photo``, never its sentence, so rewording one moves it nowhere.

    Raises:
        ValueError: a parameter the code's sentence names is missing.
    """
    if code in _FIXED:
        return _FIXED[code]
    if code is WarningCode.MISTAPPED:
        return mistapped(_given(landmark, code), _given(distance_px, code))
    if code is WarningCode.MISFIT:
        return misfit(_given(landmark, code))
    if code is WarningCode.OUTSIDE_PHOTO:
        return outside_photo(_given(distance_px, code), _given(side, code))
    if code is WarningCode.AMBIGUOUS:
        return ambiguous(marked=_given(marked, code))
    return no_margin(marked=_given(marked, code))


def _given(value: _T | None, code: WarningCode) -> _T:
    if value is None:
        raise ValueError(f"the warning {code.value!r} lacks a parameter its sentence names")
    return value


# --- refusals: input that cannot be answered honestly ----------------------------------------

POINT_AND_LINE = "Mark your friend either as a point or as a line in photo 1, not both."
SECOND_MARK_ALONE = (
    "The friend mark in photo 2 (epipole2) is used together with the one in photo 1 "
    "(epipole1); give that one too."
)
ONE_ID_PER_LANDMARK = "Give one number in landmark_ids per landmark."
LINE_FITS_NOTHING = (
    "No position along the line fits these 6 landmarks; re-check the landmarks and the line."
)
LINE_FITS_EVERYWHERE = (
    "Every point of the line fits these landmarks; add landmarks in other directions."
)
SEVEN_FIT_NOTHING = "No geometry fits these 7 landmarks; re-check them."
ONE_SURFACE_UNMARKED = (
    "The landmarks all lie on one surface, which cannot locate your friend on its own; tap "
    "your friend if you can see them."
)
FRIEND_UNDETERMINED = (
    "These landmarks do not fix where your friend is; add landmarks in other directions."
)
GEOMETRY_UNDETERMINED = (
    "These landmarks do not fix the geometry; add landmarks in other directions."
)
TOO_FEW_EPIPOLAR_LINES = (
    "These landmarks lie on too few epipolar lines to link the two photos; add landmarks in "
    "other directions."
)
FRIEND_AT_INFINITY = "The landmarks put your friend at infinity in photo 1; re-check the landmarks."
NO_PLANE = "No plane fits these landmarks."
FIVE_METHOD = "The method must be 'cremona' or 'linear'."
UNUSABLE_FOCAL = (
    "The camera's focal length in pixels is not a usable number for this photo size; give "
    "the photo's real size and focal length, or leave the camera unknown."
)


def too_few(count: int, minimum: int, purpose: str) -> str:
    return f"{count} landmarks marked; at least {minimum} are needed {purpose}."


def too_many(count: int, maximum: int) -> str:
    return f"{count} landmarks; at most {maximum} are taken here."


def mismatched(count1: int, count2: int) -> str:
    return f"Photo 1 has {count1} landmarks and photo 2 has {count2}; mark the same ones in both."


def collinear(photo: str) -> str:
    return f"All landmarks in {photo} lie on one straight line; add landmarks off that line."


def repeated(first: int, second: int, photo: str) -> str:
    return (
        f"Landmarks #{first} and #{second} are at the same place in {photo}; each landmark "
        "must be a different spot."
    )


def mark_on_landmark(label: int, photo: str) -> str:
    return (
        f"The friend mark is on landmark #{label} in {photo}; mark your friend and the "
        "landmarks at different spots."
    )


def landmarks_on_line_through(photo: str) -> str:
    return (
        f"All landmarks lie on one line through your friend in {photo}, so they say nothing "
        "about direction; add landmarks to the side of that line."
    )


# --- refusals: malformed values (read by whoever calls the API) -------------------------------


def not_a_number(name: str) -> str:
    return f"Every value of {name} must be a number."


def not_finite(name: str) -> str:
    return f"A value of {name} is not a finite number (NaN or infinity)."


def beyond_floats(name: str) -> str:
    return f"A value of {name} is too large to be a number here (beyond 1.8e308)."


def not_points(name: str, shape: tuple[int, ...]) -> str:
    return f"The value of {name} must be a list of [x, y] pairs, not an array of shape {shape}."


def not_a_point(name: str) -> str:
    return f"The value of {name} must be [x, y] or a nonzero [x, y, w]."


def not_a_pixel(name: str) -> str:
    return f"The value of {name} must be [x, y] in pixels."


def not_a_line(name: str) -> str:
    return (
        f"The value of {name} must be [a, b, c] for the line a*x + b*y + c = 0, with a or b "
        "nonzero."
    )


def not_positive(name: str) -> str:
    return f"The value of {name} must be a positive number."


def too_far(name: str, largest: float) -> str:
    return (
        f"A value of {name} is more than {largest:g} px from the origin; positions are a "
        "photo's pixels, and no photo is that large."
    )


def not_a_length(name: str, finest: float, largest: float) -> str:
    return f"The value of {name} must be between {finest:g} and {largest:g} px."


def not_precisions(name: str, count: int) -> str:
    return (
        f"The value of {name} must be one sigma in px per tap ({count} numbers) or one 2x2 "
        "covariance in px^2 per tap."
    )


def not_a_precision(name: str) -> str:
    return f"The value of {name} must be a sigma in px or a 2x2 covariance in px^2."


def not_a_covariance(name: str) -> str:
    return f"Each covariance in {name} must be symmetric and positive definite (px^2)."


def not_a_usable_covariance(name: str, finest: float, largest: float, elongated: float) -> str:
    return (
        f"Each covariance in {name} must have its sigmas (the square roots of its "
        f"eigenvalues) between {finest:g} and {largest:g} px, at most {elongated:g} times "
        "apart."
    )


def camera_without_size(name: str) -> str:
    return f"A camera model needs the photo's size: give {name} as [width, height]."


def not_a_camera(name: str, reason: str) -> str:
    return f"The value of {name} is not a camera description: {reason.rstrip('.')}."


def not_a_size(name: str) -> str:
    return f"The value of {name} must be [width, height] in pixels, both positive."


# --- drawn on the photo (short: they share the picture with the answer) -------------------------

DRAWN_FRIEND = "friend"
DRAWN_FRIEND_LIKELY = "friend?"
DRAWN_ON_CURVE = "friend on this curve"
DRAWN_BEHIND = "friend is behind you"
DRAWN_UNCLEAR = "position unclear: re-check marks"
DRAWN_FAR_OFF = "friend far off this way"


def drawn_off_photo(beyond_px: float) -> str:
    return f"friend {beyond_px:,.0f} px off"


# --- refusals of the drawing's input -----------------------------------------------------------

NOT_8_BIT = "The photo must be an 8-bit image (a uint8 numpy array)."
LABELS_WITHOUT_POINTS = "labels were given without points."
LABELS_NOT_WHOLE = "labels must be whole numbers."


def bad_photo(photo: object) -> str:
    return f"photo must be 1 or 2, got {photo!r}."


def not_a_photo(shape: tuple[int, ...]) -> str:
    return f"The photo must be (height, width, 3) BGR or (height, width) grey; got {shape}."


def labels_mismatch(labels: int, landmarks: int) -> str:
    return f"{labels} labels for {landmarks} landmarks; give one label per landmark."
