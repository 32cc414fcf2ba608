"""The solver's stable codes: why it refused (:class:`ErrorCode`, with the :class:`Reason`
that picks its sentence) and what it warns of on an answer (:class:`WarningCode`).

Every refusal carries a machine-readable ``code`` (stable: the REST API returns it and the
phones branch on it), its ``reason`` and parameters (:class:`Parameters`), and a ``message``
a person can act on (``shared_solver.refusal``); every warning a code, its parameters and its
sentence (``shared_solver.result.SolverWarning``). ``shared_solver.words`` words both.
"""

from __future__ import annotations

from enum import StrEnum
from typing import Literal, TypedDict


class ErrorCode(StrEnum):
    """Why the solver refused. The values are a public contract: never rename one."""

    INVALID_SHAPE = "invalid_shape"
    NOT_FINITE = "not_finite"
    MISMATCHED_LENGTHS = "mismatched_lengths"
    TOO_FEW_LANDMARKS = "too_few_landmarks"
    TOO_MANY_LANDMARKS = "too_many_landmarks"
    REPEATED_LANDMARKS = "repeated_landmarks"
    COLLINEAR_LANDMARKS = "collinear_landmarks"
    EPIPOLE_ON_LANDMARK = "epipole_on_landmark"
    LANDMARKS_ON_EPIPOLAR_LINE = "landmarks_on_epipolar_line"
    CONFLICTING_INPUTS = "conflicting_inputs"
    MISSING_EPIPOLE1 = "missing_epipole1"
    INVALID_PARAMETER = "invalid_parameter"
    DEGENERATE_CONFIGURATION = "degenerate_configuration"
    NO_SOLUTION = "no_solution"


# What each code means, in a line (docs/api.md's table of codes is generated from it).
MEANING: dict[ErrorCode, str] = {
    ErrorCode.INVALID_SHAPE: "a point is not two numbers, or a photo size not two",
    ErrorCode.NOT_FINITE: "a coordinate is NaN or infinite",
    ErrorCode.MISMATCHED_LENGTHS: "the two photos' landmark lists differ in length",
    ErrorCode.TOO_FEW_LANDMARKS: "fewer landmarks than what was marked needs",
    ErrorCode.TOO_MANY_LANDMARKS: "more landmarks than the solver takes",
    ErrorCode.REPEATED_LANDMARKS: "two landmarks tapped at the same spot",
    ErrorCode.COLLINEAR_LANDMARKS: "the landmarks lie on one line: they fix no geometry",
    ErrorCode.EPIPOLE_ON_LANDMARK: "the friend marked on a landmark",
    ErrorCode.LANDMARKS_ON_EPIPOLAR_LINE: "the landmarks lie on one line through the friend",
    ErrorCode.CONFLICTING_INPUTS: "the friend marked both as a point and as a line in photo 1",
    ErrorCode.MISSING_EPIPOLE1: "the friend marked in photo 2 without the mark in photo 1",
    ErrorCode.INVALID_PARAMETER: "a number out of what the solver honours (a sigma, a size, "
    "a lens, a coordinate beyond 1e6 px)",
    ErrorCode.DEGENERATE_CONFIGURATION: "the taps fit many geometries: no answer is honest",
    ErrorCode.NO_SOLUTION: "no geometry fits the taps",
}


class Reason(StrEnum):
    """Which refusal of its code: the key of its sentence (``words.refusal``). A code that
    is refused one way has one reason, named as the code. The values are a public contract:
    never rename one."""

    # invalid_shape
    NOT_A_NUMBER = "not_a_number"
    NOT_POINTS = "not_points"
    NOT_A_POINT = "not_a_point"
    NOT_A_PIXEL = "not_a_pixel"
    NOT_A_LINE = "not_a_line"
    NOT_A_DIRECTION = "not_a_direction"
    NOT_A_SIZE = "not_a_size"
    NOT_PRECISIONS = "not_precisions"
    NOT_A_PRECISION = "not_a_precision"
    NOT_8_BIT = "not_8_bit"
    NOT_A_PHOTO = "not_a_photo"
    LABELS_NOT_WHOLE = "labels_not_whole"
    # not_finite
    NOT_FINITE = "not_finite"
    BEYOND_FLOATS = "beyond_floats"
    # mismatched_lengths
    MISMATCHED_LENGTHS = "mismatched_lengths"
    ONE_ID_PER_LANDMARK = "one_id_per_landmark"
    LABELS_WITHOUT_POINTS = "labels_without_points"
    ONE_LABEL_PER_LANDMARK = "one_label_per_landmark"
    # one reason each
    TOO_FEW_LANDMARKS = "too_few_landmarks"
    TOO_MANY_LANDMARKS = "too_many_landmarks"
    REPEATED_LANDMARKS = "repeated_landmarks"
    COLLINEAR_LANDMARKS = "collinear_landmarks"
    EPIPOLE_ON_LANDMARK = "epipole_on_landmark"
    LANDMARKS_ON_EPIPOLAR_LINE = "landmarks_on_epipolar_line"
    CONFLICTING_INPUTS = "conflicting_inputs"
    MISSING_EPIPOLE1 = "missing_epipole1"
    # invalid_parameter
    TOO_FAR = "too_far"
    NOT_POSITIVE = "not_positive"
    NOT_A_LENGTH = "not_a_length"
    NOT_AN_ANGLE = "not_an_angle"
    NOT_A_COVARIANCE = "not_a_covariance"
    NOT_A_USABLE_COVARIANCE = "not_a_usable_covariance"
    NOT_A_CAMERA = "not_a_camera"
    CAMERA_WITHOUT_SIZE = "camera_without_size"
    UNUSABLE_FOCAL = "unusable_focal"
    FIVE_METHOD = "five_method"
    BAD_PHOTO = "bad_photo"
    # degenerate_configuration
    GEOMETRY_UNDETERMINED = "geometry_undetermined"
    FRIEND_UNDETERMINED = "friend_undetermined"
    ONE_SURFACE_UNMARKED = "one_surface_unmarked"
    TOO_FEW_EPIPOLAR_LINES = "too_few_epipolar_lines"
    FRIEND_AT_INFINITY = "friend_at_infinity"
    NO_PLANE = "no_plane"
    LINE_FITS_EVERYWHERE = "line_fits_everywhere"
    # no_solution
    LINE_FITS_NOTHING = "line_fits_nothing"
    SEVEN_FIT_NOTHING = "seven_fit_nothing"


_REASONS: dict[ErrorCode, tuple[Reason, ...]] = {
    ErrorCode.INVALID_SHAPE: (
        Reason.NOT_A_NUMBER,
        Reason.NOT_POINTS,
        Reason.NOT_A_POINT,
        Reason.NOT_A_PIXEL,
        Reason.NOT_A_LINE,
        Reason.NOT_A_DIRECTION,
        Reason.NOT_A_SIZE,
        Reason.NOT_PRECISIONS,
        Reason.NOT_A_PRECISION,
        Reason.NOT_8_BIT,
        Reason.NOT_A_PHOTO,
        Reason.LABELS_NOT_WHOLE,
    ),
    ErrorCode.NOT_FINITE: (Reason.NOT_FINITE, Reason.BEYOND_FLOATS),
    ErrorCode.MISMATCHED_LENGTHS: (
        Reason.MISMATCHED_LENGTHS,
        Reason.ONE_ID_PER_LANDMARK,
        Reason.LABELS_WITHOUT_POINTS,
        Reason.ONE_LABEL_PER_LANDMARK,
    ),
    ErrorCode.INVALID_PARAMETER: (
        Reason.TOO_FAR,
        Reason.NOT_POSITIVE,
        Reason.NOT_A_LENGTH,
        Reason.NOT_AN_ANGLE,
        Reason.NOT_A_COVARIANCE,
        Reason.NOT_A_USABLE_COVARIANCE,
        Reason.NOT_A_CAMERA,
        Reason.CAMERA_WITHOUT_SIZE,
        Reason.UNUSABLE_FOCAL,
        Reason.FIVE_METHOD,
        Reason.BAD_PHOTO,
    ),
    ErrorCode.DEGENERATE_CONFIGURATION: (
        Reason.GEOMETRY_UNDETERMINED,
        Reason.FRIEND_UNDETERMINED,
        Reason.ONE_SURFACE_UNMARKED,
        Reason.TOO_FEW_EPIPOLAR_LINES,
        Reason.FRIEND_AT_INFINITY,
        Reason.NO_PLANE,
        Reason.LINE_FITS_EVERYWHERE,
    ),
    ErrorCode.NO_SOLUTION: (Reason.LINE_FITS_NOTHING, Reason.SEVEN_FIT_NOTHING),
}
# The code of each reason: the code's own name when it is refused one way only.
CODE: dict[Reason, ErrorCode] = {
    reason: code for code, reasons in _REASONS.items() for reason in reasons
} | {Reason(code.value): code for code in ErrorCode if code not in _REASONS}

# The photo a refusal is about when its reason always names that one (the friend mark of
# photo 1 is the one refused); the photo of a landmark layout is a parameter instead.
REFUSAL_PHOTO: dict[Reason, Literal[1, 2]] = {
    Reason.CONFLICTING_INPUTS: 1,
    Reason.FRIEND_AT_INFINITY: 1,
}
# The reasons whose photo is a parameter: the photo whose landmarks (and friend mark) they
# are about.
REFUSAL_OF_ONE_PHOTO = frozenset(
    {
        Reason.REPEATED_LANDMARKS,
        Reason.COLLINEAR_LANDMARKS,
        Reason.EPIPOLE_ON_LANDMARK,
        Reason.LANDMARKS_ON_EPIPOLAR_LINE,
    }
)

# The parameters each reason's sentence names (docs/api.md's table); a reason absent names
# none. ``Refusal.of`` takes no other; ``marked`` may be left out (a solver's own minimum).
REFUSAL_PARAMETERS: dict[Reason, tuple[str, ...]] = {
    **dict.fromkeys(
        (
            Reason.NOT_A_NUMBER,
            Reason.NOT_A_POINT,
            Reason.NOT_A_PIXEL,
            Reason.NOT_A_LINE,
            Reason.NOT_A_DIRECTION,
            Reason.NOT_A_SIZE,
            Reason.NOT_A_PRECISION,
            Reason.NOT_FINITE,
            Reason.BEYOND_FLOATS,
            Reason.NOT_POSITIVE,
            Reason.NOT_A_COVARIANCE,
            Reason.CAMERA_WITHOUT_SIZE,
        ),
        ("field",),
    ),
    Reason.NOT_POINTS: ("field", "shape"),
    Reason.NOT_PRECISIONS: ("field", "count"),
    Reason.NOT_A_PHOTO: ("shape",),
    Reason.MISMATCHED_LENGTHS: ("counts",),
    Reason.ONE_LABEL_PER_LANDMARK: ("counts",),
    Reason.TOO_FEW_LANDMARKS: ("count", "minimum", "marked"),
    Reason.TOO_MANY_LANDMARKS: ("count", "maximum"),
    Reason.REPEATED_LANDMARKS: ("photo", "landmarks"),
    Reason.COLLINEAR_LANDMARKS: ("photo",),
    Reason.EPIPOLE_ON_LANDMARK: ("photo", "landmark"),
    Reason.LANDMARKS_ON_EPIPOLAR_LINE: ("photo",),
    Reason.TOO_FAR: ("field", "largest_px"),
    Reason.NOT_A_LENGTH: ("field", "finest_px", "largest_px"),
    Reason.NOT_AN_ANGLE: ("field", "finest_deg", "largest_deg"),
    Reason.NOT_A_USABLE_COVARIANCE: ("field", "finest_px", "largest_px", "most_elongated"),
    Reason.NOT_A_CAMERA: ("field", "detail"),
    Reason.BAD_PHOTO: ("detail",),
}

# How the friends were marked, which sets how many landmarks are needed: "both" (each in the
# other's photo), "point" or "line" (in photo 1), "none".
Marks = Literal["both", "point", "line", "none"]


class Parameters(TypedDict, total=False):
    """A refusal's parameters: what its sentence says beside its reason (each described on
    ``shared_solver.refusal.Refusal``; a reason takes the ones its sentence names)."""

    photo: Literal[1, 2]
    landmark: int
    landmarks: tuple[int, int]
    count: int
    counts: tuple[int, int]
    minimum: int
    maximum: int
    marked: Marks
    field: str
    shape: tuple[int, ...]
    finest_px: float
    largest_px: float
    most_elongated: float
    finest_deg: float
    largest_deg: float
    detail: str


class WarningCode(StrEnum):
    """What an answer warns of. The values are a public contract: never rename one."""

    CAMERA_MODEL_DISAGREES = "camera_model_disagrees"
    CAMERA_MODEL_UNSURE = "camera_model_unsure"
    ON_THE_CURVE = "on_the_curve"
    ON_THE_LEVEL = "on_the_level"
    GRAVITY_DISAGREES = "gravity_disagrees"
    HEADING_DISAGREES = "heading_disagrees"
    MARKS_DISAGREE = "marks_disagree"
    FAR_TO_THE_SIDE = "far_to_the_side"
    NOT_PINNED_DOWN = "not_pinned_down"
    BEHIND_YOU = "behind_you"
    OUTSIDE_PHOTO = "outside_photo"
    UNCERTAIN = "uncertain"
    MISTAPPED = "mistapped"
    MISFIT = "misfit"
    AMBIGUOUS = "ambiguous"
    NO_MARGIN = "no_margin"


# What each warning means, in a line, and its parameters (docs/api.md's table).
WARNING_MEANING: dict[WarningCode, str] = {
    WarningCode.CAMERA_MODEL_DISAGREES: "the taps fit no two phone photos: answered as any "
    "two cameras (the paper's geometry)",
    WarningCode.CAMERA_MODEL_UNSURE: "the taps barely fit two phone photos: the region is "
    "widened to hold either answer",
    WarningCode.ON_THE_CURVE: "too few landmarks for a point: the friend is on `curve`",
    WarningCode.ON_THE_LEVEL: "no landmark, both phones' gravity: the friend is along "
    "`curve2`, within `curve2_halfwidth` px of it",
    WarningCode.GRAVITY_DISAGREES: "the phones' gravity readings contradict the landmarks: "
    "answered from the landmarks alone",
    WarningCode.HEADING_DISAGREES: "the phones' compass headings contradict the landmarks: "
    "answered without them",
    WarningCode.MARKS_DISAGREE: "the taps disagree more than their precision says: the "
    "region is widened",
    WarningCode.FAR_TO_THE_SIDE: "the friend is (nearly) infinitely far to the side",
    WarningCode.NOT_PINNED_DOWN: "the taps do not fix the friend's position (nor its side "
    "of the camera)",
    WarningCode.BEHIND_YOU: "the friend is behind the camera of photo 2",
    WarningCode.OUTSIDE_PHOTO: "the friend is beyond the `side` edge of photo 2, `distance_px` px",
    WarningCode.UNCERTAIN: "the 95 % region is wider than a tenth of photo 2",
    WarningCode.MISTAPPED: "landmark `landmark` left out of the answer: `distance_px` px "
    "from where the others put it",
    WarningCode.MISFIT: "(a session's taps) landmark `landmark` of `photo` is tapped far "
    "outside its band",
    WarningCode.AMBIGUOUS: "several positions fit as well (`candidates`); what to add "
    "depends on how the friend was `marked`",
    WarningCode.NO_MARGIN: "the likeliest of several positions, with no region; what to add "
    "depends on how the friend was `marked`",
}

# The photo a warning is about, when it is one photo whatever its parameters: where the friend
# is in photo 2 (the answer's photo) is not said to the phone of photo 1, who sees them.
WARNING_PHOTO: dict[WarningCode, Literal[1, 2]] = {
    WarningCode.ON_THE_CURVE: 2,
    WarningCode.ON_THE_LEVEL: 2,
    WarningCode.FAR_TO_THE_SIDE: 2,
    WarningCode.BEHIND_YOU: 2,
    WarningCode.OUTSIDE_PHOTO: 2,
    WarningCode.UNCERTAIN: 2,
}
# The codes whose photo is a parameter: the photo of the landmark they name. Every other code
# is about the taps as a whole, said to both phones.
WARNING_OF_ONE_PHOTO = frozenset({WarningCode.MISFIT})
