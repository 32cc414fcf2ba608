"""What the photo endpoints answer, and the picture formats they draw in."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from backend.participants import Role

from .gravity import Gravity

ImageFormat = Literal["png", "jpeg"]
ToldBy = Literal["photo", "phone"]
MEDIA_TYPES: dict[ImageFormat, str] = {"png": "image/png", "jpeg": "image/jpeg"}


class LensInfo(BaseModel):
    """What the photo's EXIF said of its lens: the answer uses it, and needs fewer guesses."""

    focal_35mm: float = Field(description="35 mm-equivalent focal length, mm.", examples=[26.0])
    told_by: ToldBy = Field(
        description="'photo': read by the server from the uploaded photo; 'phone': read by "
        "the phone before it shrank the photo (the shrunk copy keeps no EXIF)."
    )


class GravityInfo(BaseModel):
    """Which way was down when the photo was taken, as its phone read it at the shutter."""

    down: tuple[float, float, float] = Field(
        description="Unit vector towards the ground in the photo's camera frame: x right "
        "along its rows, y down its columns, z out of the lens.",
        examples=[[0.02, 0.999, 0.04]],
    )
    sigma_deg: float = Field(description="The reading's standard deviation per axis, deg.")

    @classmethod
    def of(cls, gravity: Gravity) -> GravityInfo:
        return cls(down=gravity.down, sigma_deg=gravity.sigma_deg)


class PhotoStored(BaseModel):
    width: int = Field(
        description="Of the stored photo, px: taps are in these pixels.", examples=[2560]
    )
    height: int = Field(examples=[1920])
    scale: float = Field(
        description="Stored size / uploaded size (1.0 if not downscaled).", examples=[0.6349]
    )
    lens: LensInfo | None = Field(
        None,
        description="The lens, when the photo told it; else the answer assumes a phone's "
        "main camera, zoomed or not.",
    )
    gravity: GravityInfo | None = Field(
        None,
        description="Which way was down at the shutter, when the phone read it (the app's "
        "own camera): with both photos' the friend's level needs no landmark.",
    )
    heading: float | None = Field(
        None,
        description="Which way the lens looked at the shutter, when the phone's compass read "
        "it (the app's own camera): degrees clockwise from north, in [0, 360). Used only with "
        "both photos' gravity and heading: the stretch of the level it points to, a hint.",
        examples=[131.5],
    )
    heading_sigma_deg: float | None = Field(
        None, description="The heading's standard deviation, degrees.", examples=[15.0]
    )


class PhotoChanged(BaseModel):
    """Event ``photo``: a phone uploaded (or replaced) its photo; its taps and the answer go
    with the old one."""

    role: Role = Field(description="Whose photo.")
    version: int = Field(description="The session's version this change made.")
    photo: PhotoStored
    landmarks_needed: int = Field(description="As the state says it at this version.")
