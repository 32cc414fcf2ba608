"""What the photo endpoints answer, and the picture formats they draw in."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

ImageFormat = Literal["png", "jpeg"]
MEDIA_TYPES: dict[ImageFormat, str] = {"png": "image/png", "jpeg": "image/jpeg"}


class PhotoStored(BaseModel):
    width: int = Field(
        description="Of the stored photo, px: taps are in these pixels.", examples=[2560]
    )
    height: int = Field(examples=[1920])
    scale: float = Field(
        description="Stored size / uploaded size (1.0 if not downscaled).", examples=[0.6349]
    )
