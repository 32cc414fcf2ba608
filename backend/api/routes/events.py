"""The event stream a phone listens to: 'this changed', then it fetches the state."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Annotated

from fastapi import APIRouter, Header
from fastapi.sse import EventSourceResponse, ServerSentEvent

from backend.api.deps import StreamsDep, ViewerDep
from backend.api.responses import errors

router = APIRouter(prefix="/api/sessions", tags=["sessions"])


@router.get(
    "/{session_id}/events",
    responses={
        200: {
            "description": "text/event-stream: events joined, code (renewed), photo, taps, "
            "answer, left, expired; ': ping' comments keep it alive.",
            "content": {
                "text/event-stream": {
                    "example": 'retry: 3000\n\nid: 41\nevent: taps\ndata: {"role": "joiner", '
                    '"version": 9}\n\nid: 42\nevent: answer\ndata: {"version": 9}\n\n'
                    ": ping\n\n"
                }
            },
        },
        **errors(401, 403, 503),
    },
    response_class=EventSourceResponse,
)
async def events(
    participant: ViewerDep,
    streams: StreamsDep,
    last_event_id: Annotated[
        int | None,
        # Event ids are the database's 64-bit row ids: a larger number can name no event.
        Header(ge=0, lt=2**63, description="Resume after this event."),
    ] = None,
) -> AsyncIterator[ServerSentEvent]:
    """Server-sent events for this session (EventSource: pass ``?token=``)."""
    async for event in streams.events(participant, last_event_id):
        yield event
