"""The API fuzzed from its own OpenAPI schema (schemathesis), in process, on SQLite.

Every operation of /openapi.json gets requests made from its schema, valid and invalid;
every answer must not be a 5xx and must be what the schema documents: a documented status,
the documented content type, and a body of the documented schema (refusals included: the
one error shape). The session endpoints are reached for real: a request goes out as
generated (a made-up session id and token), or as the starter or the joiner of a live search
(both photos uploaded, landmarks tapped, an answer computed), or with the token of another
session; a request that changed the search (a 2xx PUT or DELETE) has it set up again.

Seeds are fixed (``derandomize``): a run explores the same requests every time, so a
failure is reproducible and the suite's time is steady.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import hypothesis
import pytest
import requests
import schemathesis
from fastapi import FastAPI
from hypothesis import strategies as st
from phones import PAIR, TEMPLE, scene, tapped_scene
from schemathesis.checks import not_a_server_error
from schemathesis.core.result import Ok
from schemathesis.python import asgi
from schemathesis.specs.openapi.checks import (
    content_type_conformance,
    response_schema_conformance,
    status_code_conformance,
)

from backend.main import create_app
from backend.settings import Settings
from testbed.client import pair, start

CHECKS = [
    not_a_server_error,
    status_code_conformance,
    content_type_conformance,
    response_schema_conformance,
]
# Who sends a request to a session endpoint.
IDENTITIES = ("as generated", "starter", "joiner", "stranger")
# An event stream lasts as long as its session: it is read this long, then cut.
EVENT_STREAM_SECONDS = 0.2
# Per operation, 14 operations, the most of the time spent drawing overlays and solving:
# sized for make test's 15 minutes (100 each took 55 s of CPU in a whole-suite run).
FUZZED_REQUESTS = 50

# The schema as the app documents it (no database is needed for that); each request goes
# to the app of the ``fuzzed_app`` fixture.
schema = schemathesis.openapi.from_dict(create_app(Settings(database_url="sqlite://")).openapi())


class LiveSearch:
    """A search in progress to send requests into: a session with both phones joined,
    both photos (the temple pair) and six landmarks tapped in each, and the answer."""

    def __init__(self, client: asgi.ASGIClient) -> None:
        self.client = client
        self.session_id = ""
        self.tokens: dict[str, str] = {}
        self.stranger = ""  # the token of another session
        self.changed = True

    def ready(self) -> LiveSearch:
        """Set up anew if a request changed it."""
        if self.changed:
            # testbed.client says httpx2.Client; it makes its calls on any client with
            # httpx's request(): schemathesis's (a requests.Session) has the same.
            self.stranger = start(self.client)[0].token  # type: ignore[arg-type]
            phones = pair(self.client)  # type: ignore[arg-type]
            self.session_id = phones[0].session_id
            self.tokens = {phone.role: phone.token for phone in phones}
            for phone, photo in zip(phones, PAIR, strict=True):
                phone.uploaded(TEMPLE / f"{photo}.png")
            state = tapped_scene(*phones, scene(6))
            assert state["answer"] is not None
            self.changed = False
        return self


@pytest.fixture(scope="module")
def fuzzed_app(tmp_path_factory: pytest.TempPathFactory) -> Iterator[FastAPI]:
    url = f"sqlite:///{tmp_path_factory.mktemp('fuzz') / 'buddy.db'}"
    settings = Settings(database_url=url, sweep_interval_seconds=3600)
    # Fuzzing sends many wrong join codes from one address; the live search still joins.
    limits = {"join_failures_per_client": 1_000_000, "join_failures_overall": 1_000_000}
    yield create_app(settings.model_copy(update=limits))
    asgi.shutdown_lifespans()  # schemathesis started the app's lifespan (database, sweeper)


@pytest.fixture(scope="module")
def search(fuzzed_app: FastAPI) -> Iterator[LiveSearch]:
    # Entering the client starts the app's lifespan, whichever test runs first.
    # schemathesis types an ASGI app's messages dict, Starlette MutableMapping (its stubs).
    with asgi.get_client(fuzzed_app) as client:  # type: ignore[arg-type]
        yield LiveSearch(client)


def call_and_validate(case: Any, who: str, search: LiveSearch, app: FastAPI) -> None:
    """Send ``case`` as ``who`` and run the checks on the answer."""
    headers: dict[str, str] = {}
    if "session_id" in (case.path_parameters or {}) and who != "as generated":
        search.ready()
        case.path_parameters["session_id"] = search.session_id
        token = search.stranger if who == "stranger" else search.tokens[who]
        headers["Authorization"] = f"Bearer {token}"
    if case.operation.path.endswith("/events"):
        # A stream ends when its session does: what it sent by then is checked. A busy
        # machine may not even have started answering by then: once more, with time to spare.
        try:
            response = case.call_and_validate(
                headers=headers, checks=CHECKS, app=app, timeout=EVENT_STREAM_SECONDS
            )
        except requests.exceptions.ReadTimeout:
            response = case.call_and_validate(headers=headers, checks=CHECKS, app=app, timeout=10)
    else:
        response = case.call_and_validate(headers=headers, checks=CHECKS, app=app)
    if case.method in ("PUT", "DELETE") and who in search.tokens and response.status_code < 300:
        search.changed = True


@schema.parametrize()
@hypothesis.settings(
    deadline=None,
    database=None,
    derandomize=True,
    phases=[hypothesis.Phase.explicit],  # schemathesis' examples and coverage cases
    suppress_health_check=list(hypothesis.HealthCheck),
)
def test_documented_examples_and_edge_cases_as_the_starter(
    case: Any, search: LiveSearch, fuzzed_app: FastAPI
) -> None:
    """The schema's own examples, and schemathesis' deterministic edge cases (boundary
    values, missing and wrong-typed fields, methods not allowed), sent by the starter."""
    call_and_validate(case, "starter", search, fuzzed_app)


@schema.parametrize()
@schema.given(who=st.sampled_from(IDENTITIES))
@hypothesis.settings(
    max_examples=FUZZED_REQUESTS,
    deadline=None,
    database=None,
    derandomize=True,
    # Not the explicit phase: its cases cannot draw ``who`` (the test above sends them).
    phases=[hypothesis.Phase.generate, hypothesis.Phase.shrink],
    suppress_health_check=list(hypothesis.HealthCheck),
)
def test_fuzzed_requests_from_anyone(
    case: Any, who: str, search: LiveSearch, fuzzed_app: FastAPI
) -> None:
    """Generated requests, valid and invalid, from a stranger or either phone."""
    call_and_validate(case, who, search, fuzzed_app)


def test_every_operation_is_fuzzed() -> None:
    """None is left out because schemathesis could not read its schema."""
    fuzzed = {result.ok().label for result in schema.get_all_operations() if isinstance(result, Ok)}
    documented = {
        f"{method.upper()} {path}"
        for path, item in schema.raw_schema["paths"].items()
        for method in item
    }
    assert fuzzed == documented
    assert len(fuzzed) >= 14  # as of writing
