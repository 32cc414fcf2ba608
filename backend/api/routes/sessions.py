"""The whole session as the calling phone sees it."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.responses import Response

from backend.api.deps import BaseUrlDep, ParticipantDep, StateDep
from backend.api.responses import errors, json_answer
from backend.sessions.schemas import SessionState

router = APIRouter(prefix="/api/sessions", tags=["sessions"])


@router.get("/{session_id}", response_model=SessionState, responses=errors(401, 403, 404, 503))
def session_state(participant: ParticipantDep, state: StateDep, base: BaseUrlDep) -> Response:
    """Everything a (re)connecting phone needs: who is online, photos, taps, the answer."""
    return json_answer(state.state(participant, base))
