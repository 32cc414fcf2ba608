"""Every sentence the solver says to a person: warnings on an answer and reasons for a refusal.

They reach a phone's screen, so they are written for the two friends: "your friend", "the
friend mark", "landmark #3", and a next step to take. A refusal is worded from its reason
and parameters for its reader (:func:`refusal`): "photo 1" and "photo 2" for a script, "your
photo" and "your friend's photo" for each phone of a session. A warning names none by
number ("this photo" is said only to the phone whose photo it is), so one sentence serves
both phones; which phone is told it is the
photo it is about (``errors.WARNING_PHOTO``), not its wording (:func:`warning`). Kept in
one place so the voice stays one, and so a change of wording never hides in the geometry.
"""

from __future__ import annotations

from typing import Literal, TypeVar

from .errors import Marks, Parameters, Reason, WarningCode

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
ON_THE_LEVEL = (
    "Your friend is somewhere along this band: on this level of the venue. Mark one landmark "
    "in both photos to pin down the spot."
)
GRAVITY_DISAGREES = (
    "The phones' tilt at the shutter does not fit these marks (did a phone move as it took "
    "the photo?), so the answer uses the landmarks alone."
)
HEADING_DISAGREES = (
    "The phones' compasses do not fit these marks (steel and speakers bend compasses), so the "
    "answer leaves them out."
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
    WarningCode.ON_THE_LEVEL: ON_THE_LEVEL,
    WarningCode.GRAVITY_DISAGREES: GRAVITY_DISAGREES,
    WarningCode.HEADING_DISAGREES: HEADING_DISAGREES,
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
# A refusal's sentence is made from its reason and parameters (errors.Parameters) by
# :func:`refusal`, for a reader: a script reads of "photo 1" and "photo 2", a phone in a
# session of "your photo" and "your friend's photo". Each sentence is a template that names
# its parameters ({field}, {counts[0]}, {largest_px:g}) and the photos as its reader calls them.

Reader = Literal[1, 2] | None  # the photo of the phone told; None: a script (photo 1, 2)

_PURPOSE: dict[Marks, str] = {
    "both": "when both friends are marked",
    "point": "with your friend marked",
    "line": "with a line through your friend",
    "none": "without marking your friend (tap your friend to need fewer)",
}

_REFUSAL: dict[Reason, str] = {
    # the landmarks and the friend marks (what a phone in a session can be told)
    Reason.TOO_FEW_LANDMARKS: (
        "{count} landmarks marked; at least {minimum} are needed {purpose}."
    ),
    Reason.TOO_MANY_LANDMARKS: "{count} landmarks; at most {maximum} are taken here.",
    Reason.MISMATCHED_LENGTHS: (
        "{Photo1} has {counts[0]} landmarks and {photo2} has "
        "{counts[1]}; mark the same ones in both."
    ),
    Reason.COLLINEAR_LANDMARKS: (
        "All landmarks in {photo} lie on one straight line; add landmarks off that line."
    ),
    Reason.REPEATED_LANDMARKS: (
        "Landmarks #{landmarks[0]} and #{landmarks[1]} are at the same place in "
        "{photo}; each landmark must be a different spot."
    ),
    Reason.EPIPOLE_ON_LANDMARK: (
        "The friend mark is on landmark #{landmark} in {photo}; mark your "
        "friend and the landmarks at different spots."
    ),
    Reason.LANDMARKS_ON_EPIPOLAR_LINE: (
        "All landmarks lie on one line through your friend in {photo}, so they "
        "say nothing about direction; add landmarks to the side of that line."
    ),
    Reason.CONFLICTING_INPUTS: (
        "Mark your friend either as a point or as a line in {photo1}, not both."
    ),
    Reason.MISSING_EPIPOLE1: (
        "The friend mark in {photo2} (epipole2) is used together with the one in "
        "{photo1} (epipole1); give that one too."
    ),
    Reason.FRIEND_AT_INFINITY: (
        "The landmarks put your friend at infinity in {photo1}; re-check the landmarks."
    ),
    Reason.ONE_ID_PER_LANDMARK: "Give one number in landmark_ids per landmark.",
    Reason.LINE_FITS_NOTHING: (
        "No position along the line fits these 6 landmarks; re-check the landmarks and the line."
    ),
    Reason.LINE_FITS_EVERYWHERE: (
        "Every point of the line fits these landmarks; add landmarks in other directions."
    ),
    Reason.SEVEN_FIT_NOTHING: "No geometry fits these 7 landmarks; re-check them.",
    Reason.FRAME_NOT_MATCHED: (
        "This view does not match the photo well enough to tell how the phone has turned: "
        "stand where the photo was taken, point the phone the same way, and try again."
    ),
    Reason.ONE_SURFACE_UNMARKED: (
        "The landmarks all lie on one surface, which cannot locate your friend on its own; "
        "tap your friend if you can see them."
    ),
    Reason.FRIEND_UNDETERMINED: (
        "These landmarks do not fix where your friend is; add landmarks in other directions."
    ),
    Reason.GEOMETRY_UNDETERMINED: (
        "These landmarks do not fix the geometry; add landmarks in other directions."
    ),
    Reason.TOO_FEW_EPIPOLAR_LINES: (
        "These landmarks lie on too few epipolar lines to link the two photos; add landmarks "
        "in other directions."
    ),
    Reason.NO_PLANE: "No plane fits these landmarks.",
    Reason.FIVE_METHOD: "The method must be 'cremona' or 'linear'.",
    Reason.UNUSABLE_FOCAL: (
        "The camera's focal length in pixels is not a usable number for this photo size; "
        "give the photo's real size and focal length, or leave the camera unknown."
    ),
    # malformed values (read by whoever calls the API: ``field`` is the argument's name)
    Reason.NOT_A_NUMBER: "Every value of {field} must be a number.",
    Reason.NOT_FINITE: "A value of {field} is not a finite number (NaN or infinity).",
    Reason.BEYOND_FLOATS: "A value of {field} is too large to be a number here (beyond 1.8e308).",
    Reason.NOT_POINTS: (
        "The value of {field} must be a list of [x, y] pairs, not an array of shape {shape}."
    ),
    Reason.NOT_A_POINT: "The value of {field} must be [x, y] or a nonzero [x, y, w].",
    Reason.NOT_A_PIXEL: "The value of {field} must be [x, y] in pixels.",
    Reason.NOT_A_LINE: (
        "The value of {field} must be [a, b, c] for the line a*x + b*y + c = 0, with a "
        "or b nonzero."
    ),
    Reason.NOT_A_DIRECTION: (
        "The value of {field} must be [x, y, z], the direction of gravity (down) in "
        "the photo's camera frame, not all zero."
    ),
    Reason.NOT_POSITIVE: "The value of {field} must be a positive number.",
    Reason.TOO_FAR: (
        "A value of {field} is more than {largest_px:g} px from the origin; "
        "positions are a photo's pixels, and no photo is that large."
    ),
    Reason.NOT_A_LENGTH: (
        "The value of {field} must be between {finest_px:g} and {largest_px:g} px."
    ),
    Reason.NOT_AN_ANGLE: (
        "The value of {field} must be between {finest_deg:g} and {largest_deg:g} degrees."
    ),
    Reason.NOT_PRECISIONS: (
        "The value of {field} must be one sigma in px per tap ({count} numbers) "
        "or one 2x2 covariance in px^2 per tap."
    ),
    Reason.NOT_A_PRECISION: (
        "The value of {field} must be a sigma in px or a 2x2 covariance in px^2."
    ),
    Reason.NOT_A_COVARIANCE: (
        "Each covariance in {field} must be symmetric and positive definite (px^2)."
    ),
    Reason.NOT_A_USABLE_COVARIANCE: (
        "Each covariance in {field} must have its sigmas (the square roots of its "
        "eigenvalues) between {finest_px:g} and {largest_px:g} px, at most "
        "{most_elongated:g} times apart."
    ),
    Reason.CAMERA_WITHOUT_SIZE: (
        "A camera model needs the photo's size: give {field} as [width, height]."
    ),
    Reason.NOT_A_CAMERA: "The value of {field} is not a camera description: {detail}.",
    Reason.NOT_A_SIZE: "The value of {field} must be [width, height] in pixels, both positive.",
    # the drawing's input
    Reason.NOT_8_BIT: "The photo must be an 8-bit image (a uint8 numpy array).",
    Reason.LABELS_WITHOUT_POINTS: "labels were given without points.",
    Reason.LABELS_NOT_WHOLE: "labels must be whole numbers.",
    Reason.BAD_PHOTO: "photo must be 1 or 2, got {detail}.",
    Reason.NOT_A_PHOTO: (
        "The photo must be (height, width, 3) BGR or (height, width) grey; got {shape}."
    ),
    Reason.ONE_LABEL_PER_LANDMARK: (
        "{counts[0]} labels for {counts[1]} landmarks; give one label per landmark."
    ),
}


def refusal(reason: Reason, parameters: Parameters, *, reader: Reader = None) -> str:
    """A refusal's sentence, from its reason and its parameters: the one wording of each
    (``shared_solver.refusal.Refusal`` carries all three), for ``reader``: None, a script,
    reads "photo 1" and "photo 2"; the phone of photo 1 or 2 reads "your photo" for its own
    and "your friend's photo" for the other.

    Raises:
        ValueError: a parameter the reason's sentence names is missing.
    """

    def photo(number: Literal[1, 2]) -> str:
        if reader is None:
            return f"photo {number}"
        return "your photo" if number == reader else "your friend's photo"

    # A sentence names the photos for its reader, never by number: {photo} is the photo the
    # parameter points at, {photo1} and {photo2} the two, {Photo1} at a sentence's start.
    names: dict[str, object] = {
        **parameters,
        "photo1": photo(1),
        "photo2": photo(2),
        "Photo1": _capital(photo(1)),
        "purpose": _PURPOSE[parameters["marked"]] if "marked" in parameters else "here",
    }
    if "photo" in parameters:
        names["photo"] = photo(parameters["photo"])
    if "detail" in parameters:  # a clause: the sentence that names it ends it
        names["detail"] = parameters["detail"].rstrip(".")
    try:
        return _REFUSAL[reason].format_map(names)
    except KeyError as missing:
        raise ValueError(
            f"the refusal {reason.value!r} lacks a parameter its sentence names: {missing}"
        ) from None


def _capital(text: str) -> str:
    return text[0].upper() + text[1:]


# --- drawn on the photo (short: they share the picture with the answer) -------------------------

DRAWN_FRIEND = "friend"
DRAWN_FRIEND_LIKELY = "friend?"
DRAWN_ON_CURVE = "friend on this curve"
DRAWN_ON_LEVEL = "friend along this band"
DRAWN_COMPASS_HINT = "friend along this band; compass says about here"
DRAWN_BEHIND = "friend is behind you"
DRAWN_UNCLEAR = "position unclear: re-check marks"
DRAWN_FAR_OFF = "friend far off this way"


def drawn_off_photo(beyond_px: float) -> str:
    return f"friend {beyond_px:,.0f} px off"
