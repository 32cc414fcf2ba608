"""#3 is the same colour on both phones and in the server's drawings: the app's palette
(TypeScript) and the solver's (Python) are the same table."""

from __future__ import annotations

import re
from pathlib import Path

from shared_solver.drawing.palette import (
    FRIEND_COLOUR_HEX,
    LANDMARK_COLOURS_HEX,
    SUSPECT_COLOUR_HEX,
)

PALETTE_TS = Path(__file__).parents[1] / "frontend" / "src" / "palette.ts"


def test_the_app_paints_landmarks_like_the_drawings() -> None:
    source = PALETTE_TS.read_text()
    table = re.search(r"LANDMARK_COLOURS[^=]*=\s*\[(.*?)\]", source, re.S)
    assert table is not None, "palette.ts must define LANDMARK_COLOURS"
    colours = [c.lower() for c in re.findall(r"#[0-9a-fA-F]{6}", table.group(1))]
    assert colours == [c.lower() for c in LANDMARK_COLOURS_HEX]
    assert FRIEND_COLOUR_HEX.lower() in source.lower()
    assert SUSPECT_COLOUR_HEX.lower() in source.lower()
