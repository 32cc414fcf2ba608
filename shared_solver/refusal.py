"""A refusal: why the solver gives no answer, as its stable code, the reason that picks its
sentence, that sentence's parameters and the sentence (``words.refusal``); and the one
exception type that carries it (:class:`SolverError`). Like a warning
(``result.SolverWarning``), a refusal is worded from its code and parameters, never read
back from its sentence: a session words it again for each phone (``Refusal.said_to``).
"""

from __future__ import annotations

from typing import Literal, Unpack

from pydantic import BaseModel, ConfigDict, Field

from . import words
from .errors import (
    CODE,
    REFUSAL_PARAMETERS,
    REFUSAL_PHOTO,
    ErrorCode,
    Marks,
    Parameters,
    Reason,
)


class Refusal(BaseModel):
    """Why there is no answer: ``code`` (docs/api.md lists them), ``reason`` (which refusal of
    the code), the parameters its sentence names (null when it names none) and ``message``,
    the sentence made from them for its reader."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    code: ErrorCode
    reason: Reason = Field(description="Which refusal of the code: the key of its sentence.")
    photo: Literal[1, 2] | None = Field(
        None,
        description="The photo it is about (its landmarks, its friend mark); null: both or "
        "neither.",
    )
    landmark: int | None = Field(None, description="The landmark's number (#3).")
    landmarks: tuple[int, int] | None = Field(
        None, description="repeated_landmarks: the two landmarks at one place (#2 and #5)."
    )
    count: int | None = Field(
        None,
        description="How many landmarks were given (not_precisions: how many sigmas are needed).",
    )
    counts: tuple[int, int] | None = Field(
        None,
        description="mismatched_lengths: photo 1's and photo 2's landmarks; "
        "one_label_per_landmark: the labels and the landmarks.",
    )
    minimum: int | None = Field(None, description="The fewest landmarks taken.")
    maximum: int | None = Field(None, description="The most landmarks taken.")
    marked: Marks | None = Field(
        None,
        description="How the friends were marked, which sets the minimum: 'both' (each in "
        "the other's photo), 'point' or 'line' (in photo 1), 'none'.",
    )
    field: str | None = Field(None, description="The argument refused (points1, camera2...).")
    shape: tuple[int, ...] | None = Field(None, description="The shape given instead.")
    finest_px: float | None = Field(None, description="The smallest length honoured, px.")
    largest_px: float | None = Field(None, description="The largest length honoured, px.")
    most_elongated: float | None = Field(
        None, description="How many times apart a covariance's two sigmas may be."
    )
    finest_deg: float | None = Field(None, description="The finest sensor sigma honoured, deg.")
    largest_deg: float | None = Field(None, description="The largest sensor sigma honoured, deg.")
    detail: str | None = Field(
        None, description="not_a_camera: what is wrong with it; bad_photo: the value given."
    )
    message: str = Field(description="The sentence a person reads.")
    reader: Literal[1, 2] | None = Field(
        None,
        description="The photo of the phone it is said to (its sentence calls that one "
        "'your photo', the other 'your friend's photo'), so a phone can word it in its own "
        "language; null: said to a script (photo 1, photo 2).",
    )

    @classmethod
    def of(cls, reason: Reason, **parameters: Unpack[Parameters]) -> Refusal:
        """The refusal ``reason`` with these parameters and its sentence for a script
        (photo 1, photo 2); about the photo its reason always names
        (``errors.REFUSAL_PHOTO``).

        Raises:
            ValueError: a parameter the reason's sentence names is missing, or one it does
                not name is given.
        """
        unnamed = set(parameters) - set(REFUSAL_PARAMETERS.get(reason, ()))
        if unnamed:
            raise ValueError(f"the refusal {reason.value!r} names no {sorted(unnamed)}")
        if reason in REFUSAL_PHOTO:
            parameters["photo"] = REFUSAL_PHOTO[reason]
        return cls(
            code=CODE[reason],
            reason=reason,
            message=words.refusal(reason, parameters),
            **parameters,
        )

    @property
    def parameters(self) -> Parameters:
        """What its sentence says beside its reason."""
        given = self.model_dump(exclude_none=True, exclude={"code", "reason", "message", "reader"})
        return Parameters(**given)  # type: ignore[typeddict-item]

    def said_to(self, reader: words.Reader) -> Refusal:
        """The same refusal worded for ``reader``: the phone of photo 1 or 2 (its photo is
        "your photo"), or None, a script."""
        message = words.refusal(self.reason, self.parameters, reader=reader)
        return self.model_copy(update={"message": message, "reader": reader})


class SolverError(ValueError):
    """Input the solver cannot answer honestly.

    Attributes:
        refusal: its code, reason, parameters and sentence (:class:`Refusal`).
        code: one of :class:`~shared_solver.errors.ErrorCode`, stable across versions.
        message: a plain-English sentence saying what to do about it (for a script).
    """

    def __init__(self, reason: Reason | Refusal, **parameters: Unpack[Parameters]) -> None:
        self.refusal = reason if isinstance(reason, Refusal) else Refusal.of(reason, **parameters)
        super().__init__(self.refusal.message)

    @property
    def code(self) -> ErrorCode:
        return self.refusal.code

    @property
    def message(self) -> str:
        return self.refusal.message

    def __repr__(self) -> str:
        return f"SolverError({self.code.value!r}, {self.message!r})"
