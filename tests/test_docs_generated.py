"""The docs generated from the code are what the code says now (docsgen/)."""

from __future__ import annotations

import pytest

from backend.errors import MEANING, STATUS, ErrorCode
from docsgen import error_codes
from shared_solver import errors as solver_errors


def test_every_code_has_a_meaning() -> None:
    assert set(MEANING) == set(ErrorCode) == set(STATUS)
    assert set(solver_errors.MEANING) == set(solver_errors.ErrorCode)
    assert set(solver_errors.WARNING_MEANING) == set(solver_errors.WarningCode)


def test_the_api_doc_lists_every_code_as_the_code_says() -> None:
    assert error_codes.main(["--check"]) == 0, "renew it: python -m docsgen.error_codes"
    listed = error_codes.API_DOC.read_text(encoding="utf-8")
    for code in [*ErrorCode, *solver_errors.ErrorCode, *solver_errors.WarningCode]:
        assert f"| `{code}` |" in listed


def test_a_changed_meaning_makes_the_doc_stale(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(MEANING, ErrorCode.BUSY, "a meaning nobody wrote down")
    assert error_codes.main(["--check"]) == 1


def test_a_changed_warning_meaning_makes_the_doc_stale(monkeypatch: pytest.MonkeyPatch) -> None:
    code = solver_errors.WarningCode.BEHIND_YOU
    monkeypatch.setitem(solver_errors.WARNING_MEANING, code, "a meaning nobody wrote down")
    assert error_codes.main(["--check"]) == 1
