"""A change of taps that leaves the solver's problem as it was is answered from the answer
before it (backend.taps.problem.KnownFit): what the phones are told is what solving
again tells them."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from fastapi.testclient import TestClient
from phones import landmarks, photos_uploaded, scene

from backend.taps import problem
from shared_solver.drawing.layout import answer_drawing
from testbed.client import pair

SHOWN = ("answer", "answer_error", "landmarks_needed", "taps")


def played(client: TestClient, photos: tuple[bytes, bytes]) -> list[dict[str, Any]]:
    """A search tapped one landmark at a time (the starter first, then the joiner finding
    it), a landmark mistapped and moved back: what each PUT answered."""
    starter, joiner = pair(client)
    photos_uploaded(starter, joiner, photos)
    s = scene(6, seed=3)
    mistapped = s.landmarks2.copy()
    mistapped[4] += (0.0, 60.0)  # #5 60 px off: flagged until moved back
    states = []
    for n in range(1, 7):
        states.append(starter.tapped(landmarks=landmarks(s.landmarks1[:n]), friend=s.epipole1))
        states.append(joiner.tapped(landmarks=landmarks(mistapped[:n])))
    states.append(joiner.tapped(landmarks=landmarks(s.landmarks2)))
    states.append(starter.tapped(landmarks=landmarks(s.landmarks1[:5]), friend=s.epipole1))
    return [{key: state[key] for key in SHOWN} for state in states]


def test_answers_from_a_known_fit_are_those_of_solving_again(
    client: TestClient, temple_photos: tuple[bytes, bytes], monkeypatch: pytest.MonkeyPatch
) -> None:
    used = []
    remembered = problem.KnownFit.result

    def result(known: problem.KnownFit) -> Any:
        used.append(known.task)
        return remembered(known)

    drawn = []
    draw = answer_drawing  # what problem calls, by this name

    def drawing(*args: Any, **kwargs: Any) -> Any:
        drawn.append(kwargs["photo"])
        return draw(*args, **kwargs)

    monkeypatch.setattr(problem.KnownFit, "result", result)
    monkeypatch.setattr(problem, "answer_drawing", drawing)
    with_known = played(client, temple_photos)
    assert len(used) >= 6  # the starter's unmatched landmarks, the joiner's judged ones
    drawn_with_known = len(drawn)
    monkeypatch.setattr(problem, "known_fit", lambda *_, **__: None)
    drawn.clear()
    solved_again = played(client, temple_photos)
    assert with_known == solved_again  # the known fit's drawings reused are those drawn again
    assert drawn_with_known < len(drawn)  # not drawn again for a known fit (here 12 of 18)
    flagged = [shown["answer"]["in_photo"]["joiner"]["misfits"] for shown in with_known[9:]]
    assert flagged == [[5], [5], [5], [], []]
    assert np.isfinite(with_known[-1]["answer"]["in_photo"]["joiner"]["friend"]).all()
