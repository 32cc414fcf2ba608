"""The README's example runs and prints what the README says it prints."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from backend.main import create_app
from backend.settings import Settings

README = Path(__file__).parents[1] / "README.md"


def example(name: str = "solve") -> str:
    text = README.read_text()
    marker = text.index(f"<!-- example: {name}")
    block = re.search(r"```python\n(.*?)```", text[marker:], re.S)
    assert block is not None
    return block.group(1)


def test_readme_example_prints_what_it_promises() -> None:
    output = io.StringIO()
    with contextlib.redirect_stdout(output):
        exec(compile(example(), "README.md", "exec"), {})  # our own README
    first, second, third = output.getvalue().splitlines()
    printed = re.match(r"(\w+) \(([\d.]+), ([\d.]+)\) (\w+)", first)
    assert printed is not None, first
    method, x, y, quality = printed.groups()
    assert method == "five_point_epipole"
    assert quality == "good"
    assert abs(float(x) - 543.9) < 1.0
    assert abs(float(y) - 599.2) < 1.0
    axes = [float(v) for v in re.findall(r"[\d.]+", second)]
    assert abs(axes[0] - 4.4) < 0.2
    assert abs(axes[1] - 2.9) < 0.2
    phone = re.match(r"(\w+) \(([\d.]+), ([\d.]+)\)", third)
    assert phone is not None, third
    assert phone.group(1) == "pinhole_epipole"
    assert abs(float(phone.group(2)) - 538.8) < 0.1
    assert abs(float(phone.group(3)) - 600.8) < 0.1


def test_readme_session_script_finds_the_buddy(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The httpx2 script, run against the app in-process instead of a server on :8000."""
    script = example("session")
    opening = 'http = httpx2.Client(base_url="http://127.0.0.1:8000")'
    assert opening in script
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'readme.db'}")
    monkeypatch.chdir(README.parent)
    output = io.StringIO()
    with TestClient(create_app(settings)) as client, contextlib.redirect_stdout(output):
        exec(
            compile(script.replace(opening, "http = client"), "README.md", "exec"),
            {"client": client},
        )
    assert output.getvalue().strip() == "pinhole_epipole [521.9, 74.0] fair"


def test_readme_lists_every_setting_with_its_default() -> None:
    text = README.read_text()
    for name, field in Settings.model_fields.items():
        row = re.search(rf"^\| `BUDDY_{name.upper()}` \| `([^`]*)` \|", text, re.M)
        assert row is not None, name
        assert row.group(1) == str(field.default), name
