"""Buddy Search geometry: find friend 1 in friend 2's photo from a few shared landmarks.

Kasten & Werman, "Two view constraints on the epipoles from few correspondences": with
friend 2 tapped in photo 1 (epipole ``e1``), 4 landmarks put friend 1 on a conic in photo 2,
5 fix the point ``e2``, and a line through friend 2 with 6 landmarks fixes both epipoles.

Three layers, as in PoseLib: exact few-landmark solvers (:func:`epipole_conic`,
:func:`epipole_from_five`, :func:`epipoles_from_six`, :func:`fundamental_from_epipoles`),
estimation under tap noise (maximum likelihood, mis-tapped landmarks, plane model,
uncertainty), and :func:`solve`, which picks among them. :func:`draw_overlay` draws the
answer on a photo. Pure numpy and OpenCV: no web, no database.

Pixels everywhere: x right, y down, origin at the top-left (OpenCV's convention).
"""

from .drawing.overlay import draw_overlay
from .drawing.palette import landmark_colour, landmark_colour_hex
from .errors import ErrorCode, Reason, WarningCode
from .estimation.camera import Camera
from .estimation.ranking import EpipoleCandidate, epipoles_from_six
from .minimal.conic import epipole_conic
from .minimal.five_point import epipole_from_five
from .minimal.two_epipoles import fundamental_from_epipoles
from .refusal import Refusal, SolverError
from .result import (
    CameraEstimate,
    Candidate,
    Ellipse,
    SolveResult,
    SolverWarning,
    Uncertainty,
)
from .solve import fewest_landmarks, solve

__all__ = [
    "Camera",
    "CameraEstimate",
    "Candidate",
    "Ellipse",
    "EpipoleCandidate",
    "ErrorCode",
    "Reason",
    "Refusal",
    "SolveResult",
    "SolverError",
    "SolverWarning",
    "Uncertainty",
    "WarningCode",
    "draw_overlay",
    "epipole_conic",
    "epipole_from_five",
    "epipoles_from_six",
    "fewest_landmarks",
    "fundamental_from_epipoles",
    "landmark_colour",
    "landmark_colour_hex",
    "solve",
]
