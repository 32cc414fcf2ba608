"""Starting a search, joining it, and ending it."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.responses import Response

from backend.api.deps import BaseUrlDep, ClientAddressDep, PairingDep, ParticipantDep
from backend.api.responses import errors, json_answer
from backend.pairing.schemas import CreatedSession, Joined, JoinRequest

router = APIRouter(prefix="/api/sessions", tags=["sessions"])


@router.post("", status_code=201, response_model=CreatedSession, responses=errors(503))
def create_session(pairing: PairingDep, base: BaseUrlDep) -> Response:
    """Start a search: a session, a join code for your friend, and your token."""
    return json_answer(pairing.create(base), status_code=201)


@router.post("/join", response_model=Joined, responses=errors(400, 404, 413, 422, 429, 503))
def join_session(request: JoinRequest, pairing: PairingDep, client: ClientAddressDep) -> Response:
    """Join your friend's search with its eight-digit code (single use, valid 10 minutes).
    Wrong codes are limited per client address and overall (429 ``too_many_attempts`` with
    ``Retry-After``, seconds), and a code that wrong codes named five times is renewed."""
    return json_answer(pairing.join(request.code, client))


@router.delete("/{session_id}", status_code=204, responses=errors(401, 403, 503))
def delete_session(participant: ParticipantDep, pairing: PairingDep) -> Response:
    """Delete now: photos, taps and answer are gone at once, for both phones."""
    pairing.delete(participant)
    return Response(status_code=204)
