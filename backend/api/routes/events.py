"""The event stream a phone listens to: each change of its session, with what the phone
needs to show it (``SessionEvents``)."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Annotated, Any

from fastapi import APIRouter, Header
from fastapi.sse import EventSourceResponse, ServerSentEvent
from pydantic.json_schema import models_json_schema

from backend.api.deps import StreamsDep, ViewerDep
from backend.api.responses import errors
from backend.sessions.schemas import SessionEvents

router = APIRouter(prefix="/api/sessions", tags=["sessions"])

PATH = "/api/sessions/{session_id}/events"
_REF = "#/components/schemas/{model}"


@router.get(
    "/{session_id}/events",
    responses={
        200: {
            "description": "text/event-stream: events joined, code (renewed), photo, taps, "
            "answer, left, expired, each with its data (SessionEvents); ': ping' comments "
            "keep it alive.",
            "content": {
                "text/event-stream": {
                    "example": 'retry: 3000\n\nid: 41\nevent: taps\ndata: {"role": "joiner", '
                    '"version": 9, "taps": {"landmarks": [...], "friend": null, '
                    '"friend_line": null}, "landmarks_needed": 0}\n\nid: 42\nevent: answer\n'
                    'data: {"version": 9, "answer": {...}, "answer_error": null, '
                    '"landmarks_needed": 0}\n\n: ping\n\n'
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


def document_events(schema: dict[str, Any]) -> None:
    """Put each event's data model among the schema's components (the phone app's types are
    generated from them), and describe the stream's events as OpenAPI 3.2 does for
    ``text/event-stream`` (``itemSchema``, as FastAPI writes it for a typed stream)."""
    _, top = models_json_schema([(SessionEvents, "serialization")], ref_template=_REF)
    components = schema.setdefault("components", {}).setdefault("schemas", {})
    for name, model in top["$defs"].items():
        components.setdefault(name, model)  # shared models (Taps, Answer) are FastAPI's own
    kinds = []
    for event, field in SessionEvents.model_fields.items():
        assert isinstance(field.annotation, type)  # each a model of its own
        data = {
            "type": "string",
            "contentMediaType": "application/json",
            "contentSchema": {"$ref": _REF.format(model=field.annotation.__name__)},
        }
        kinds.append(
            {
                "type": "object",
                "required": ["event", "data"],
                "properties": {
                    "event": {"const": event},
                    "data": data,
                    "id": {"type": "string"},
                    "retry": {"type": "integer", "minimum": 0},
                },
            }
        )
    answer = schema["paths"][PATH]["get"]["responses"]["200"]["content"]["text/event-stream"]
    answer["itemSchema"] = {"oneOf": kinds}
