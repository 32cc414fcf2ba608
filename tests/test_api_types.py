"""The phone app's API types are the app's own OpenAPI schema, as committed.

``frontend/src/generated/openapi.ts`` is what openapi-typescript makes of
``python -m backend.openapi``: the build renews it when the backend changes, and this test
fails when the committed copy is not what the schema gives now (`make test` runs it beside
a build that uses the committed copy as it is, so a stale commit cannot pass by being
renewed on the way).
"""

from __future__ import annotations

import subprocess
from pathlib import Path

from backend.openapi import schema

FRONTEND = Path(__file__).parents[1] / "frontend"
GENERATED = FRONTEND / "src" / "generated" / "openapi.ts"
GENERATOR = FRONTEND / "node_modules" / ".bin" / "openapi-typescript"
RENEW = "renew them: .venv/bin/python -m backend.openapi | (cd frontend && npm run api-types)"


def check(output: Path) -> subprocess.CompletedProcess[str]:
    """openapi-typescript's own check of ``output`` against the schema the app serves now."""
    assert GENERATOR.is_file(), "the phone app's npm packages are missing: make test installs them"
    return subprocess.run(
        [str(GENERATOR), "-o", str(output), "--check"],
        input=schema(),
        cwd=FRONTEND,
        capture_output=True,
        text=True,
        check=False,
        timeout=120,
    )


def test_the_committed_api_types_are_the_schemas() -> None:
    checked = check(GENERATED)
    assert checked.returncode == 0, f"the API types are stale; {RENEW}\n{checked.stdout}"


def test_the_check_fails_on_a_stale_copy(tmp_path: Path) -> None:
    """The check itself can fail: a copy that lacks a field of the schema is refused."""
    committed = GENERATED.read_text()
    assert "friend_line?:" in committed  # a field of the taps a phone sends
    stale = tmp_path / "openapi.ts"
    stale.write_text(committed.replace("friend_line?:", "epipolar_line1?:"))
    assert check(stale).returncode != 0
