"""What a phone shows after an event of its session's stream, taken in as the phone app does
(``frontend/src/changes.ts``): for the load benchmark's phones (``benchmarks/searches.py``)
and the tests that check each event carries what reading the state would show.

A change's event applies to the state of the version before it (an ``answer`` to its own
version); a phone whose state is elsewhere, or an event that cannot tell (taps overtaken, a
join code renewed), must fetch the state instead.
"""

from __future__ import annotations

import copy
from typing import Any

State = dict[str, Any]


def take_in(shown: State | None, event: str, data: Any) -> State | None:
    """The state after ``event`` (its JSON ``data``): ``shown`` itself when it shows that
    already, a new state, or None when the phone must fetch the state."""
    if shown is None or not isinstance(data, dict):
        return None
    if event in {"joined", "left"}:
        return _presence(shown, data)
    if not isinstance(data.get("version"), int):
        return None
    if event == "answer":
        return _answer(shown, data)
    return _change(shown, event, data)


def _change(shown: State, event: str, data: dict[str, Any]) -> State | None:
    """A photo or taps of a phone, or another change (a renewed code: no event tells it)."""
    version = data["version"]
    if version <= shown["version"]:
        return shown
    if event not in {"photo", "taps"} or version > shown["version"] + 1:
        return None  # a change missed, or one no event can tell
    if data.get("landmarks_needed") is None:
        return None  # overtaken: the count is the state's to say
    state = _changed(shown, version)
    role = data["role"]
    if event == "photo":
        state["photos"][role] = data["photo"]
        state["taps"][role] = None
    else:
        state["taps"][role] = data["taps"]
    state["landmarks_needed"] = data["landmarks_needed"]
    return state


def _changed(shown: State, version: int) -> State:
    """A new version: the answer of the one before goes."""
    state = copy.deepcopy(shown)
    state |= {"version": version, "answer": None, "answer_version": None, "answer_error": None}
    return state


def _presence(shown: State, data: dict[str, Any]) -> State | None:
    role, online, version = data["role"], data["online"], data.get("version")
    if version is None:  # a phone's stream opened or closed
        if shown["participants"][role]["online"] == online:
            return shown
        state = copy.deepcopy(shown)
        state["participants"][role]["online"] = online
        return state
    if version <= shown["version"]:
        return shown
    if version > shown["version"] + 1:
        return None
    state = _changed(shown, version)  # the joiner joined: the starter's code is used up
    state["participants"][role] = {"joined": True, "online": online}
    return state | {"join_code": None, "join_code_expires_at": None, "join_url": None}


def _answer(shown: State, data: dict[str, Any]) -> State | None:
    version = data["version"]
    if version < shown["version"]:
        return shown
    if version > shown["version"]:
        return None
    if shown.get("answer") is not None or shown.get("answer_error") is not None:
        return shown
    errors = data["answer_error"]
    return shown | {
        "answer": data["answer"],
        "answer_version": version if data["answer"] is not None else None,
        "answer_error": None if errors is None else errors[shown["you"]],
        "landmarks_needed": data["landmarks_needed"],
    }
