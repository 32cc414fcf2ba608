"""The limits the phone app and the server share, read from ``limits.json``: the one source
(the app imports the same file; tests check both read it)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

_LIMITS: dict[str, Any] = json.loads(Path(__file__).with_name("limits.json").read_text())

STORED_PHOTO_SIDE: int = _LIMITS["stored_photo_side"]
MAX_LANDMARKS: int = _LIMITS["max_landmarks"]
MAX_LANDMARK_ID: int = _LIMITS["max_landmark_id"]
JOIN_CODE_LENGTH: int = _LIMITS["join_code_length"]
# The event types a phone's stream carries (backend.eventstream.log.EventType).
EVENTS: tuple[str, ...] = tuple(_LIMITS["events"])
