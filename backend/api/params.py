"""Path and query parameters that several routes share."""

from __future__ import annotations

from typing import Annotated

from fastapi import Path, Query

from backend.participants import Role
from backend.photos.schemas import ImageFormat

RoleParam = Annotated[
    Role, Path(description="Whose photo: the friend who started the search, or who joined it.")
]
FormatParam = Annotated[ImageFormat, Query(description="jpeg (photos: small, fast) or png")]
