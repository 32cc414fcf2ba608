"""Every refusal has one stable code, and every code one HTTP status, wherever it is used."""

from __future__ import annotations

from fastapi.testclient import TestClient

from backend.errors import STATUS, ErrorCode
from backend.eventstream.log import EventType
from backend.limits import EVENTS
from shared_solver import ErrorCode as SolverCode


def test_every_code_has_exactly_one_status() -> None:
    assert set(STATUS) == set(ErrorCode)
    assert all(400 <= status < 600 for status in STATUS.values())
    # The solver's codes are all 422; a code both use means the same, with the same status.
    for shared in {code.value for code in SolverCode} & {code.value for code in ErrorCode}:
        assert STATUS[ErrorCode(shared)] == 422, shared


def test_the_documented_examples_use_each_code_with_its_status(client: TestClient) -> None:
    schema = client.get("/openapi.json").json()
    solver_codes = {code.value for code in SolverCode}
    seen = 0
    for path in schema["paths"].values():
        for operation in path.values():
            for status, answer in operation["responses"].items():
                example = answer.get("content", {}).get("application/json", {}).get("example")
                if not isinstance(example, dict) or "error" not in example:
                    continue
                code = example["error"]["code"]
                expected = 422 if code in solver_codes else STATUS[ErrorCode(code)]
                assert int(status) == expected, (code, status)
                seen += 1
    assert seen > 20


def test_the_event_types_are_the_shared_list() -> None:
    """The phone app reads the event names from backend/limits.json, as the server does."""
    assert [event.value for event in EventType] == list(EVENTS)
