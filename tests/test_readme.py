"""The README and docs/api.md: every example runs and prints what the text says it prints,
the curl flow against a live server; the README is short and its links and pictures exist."""

from __future__ import annotations

import contextlib
import io
import json
import re
import subprocess
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from backend.main import create_app
from backend.settings import Settings
from deploy.replica import serve

ROOT = Path(__file__).parents[1]
README = ROOT / "README.md"
API = ROOT / "docs" / "api.md"
DEPLOY = ROOT / "docs" / "deploy.md"


def example(name: str, page: Path = README, language: str = "python") -> str:
    text = page.read_text()
    marker = text.index(f"<!-- example: {name}")
    block = re.search(rf"```{language}\n(.*?)```", text[marker:], re.S)
    assert block is not None
    return block.group(1)


def test_readme_example_prints_what_it_promises() -> None:
    output = io.StringIO()
    with contextlib.redirect_stdout(output):
        exec(compile(example("solve"), "README.md", "exec"), {})  # our own README
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


def test_the_python_session_example_finds_the_friend(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """docs/api.md's httpx2 script, against the app in-process instead of a server."""
    script = example("session", API)
    opening = 'http = httpx2.Client(base_url="http://127.0.0.1:8000")'
    assert opening in script
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'readme.db'}")
    monkeypatch.chdir(ROOT)
    output = io.StringIO()
    with TestClient(create_app(settings)) as client, contextlib.redirect_stdout(output):
        exec(
            compile(script.replace(opening, "http = client"), "docs/api.md", "exec"),
            {"client": client},
        )
    printed = output.getvalue().strip()
    assert printed == "pinhole_epipole [521.8, 74.1] solved"
    assert "# pinhole_epipole [521.8, 74.1] solved" in script


def test_the_curl_flow_runs_against_a_live_server(tmp_path: Path) -> None:
    """The README's curl commands, as written, against uvicorn on a loopback port."""
    script = example("curl", README, "sh")
    assert script.startswith("B=http://127.0.0.1:8000\n")
    # It names tests/data/temple/...: that folder, linked into the folder it runs in.
    (tmp_path / "tests" / "data").mkdir(parents=True)
    (tmp_path / "tests" / "data" / "temple").symlink_to(ROOT / "tests" / "data" / "temple")
    with serve(tmp_path) as server:
        run = subprocess.run(
            ["bash", "-euo", "pipefail", "-c", f"B={server.base_url}\n" + script.split("\n", 1)[1]],
            cwd=tmp_path,
            env={"PATH": "/usr/bin:/bin", "HOME": str(tmp_path)},
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    solved = json.loads(lines[0])
    assert abs(solved[0] - 543.9) < 1.0
    assert abs(solved[1] - 599.2) < 1.0
    stored = [json.loads(line) for line in lines[1:3]]
    no_sensors = {"gravity": None, "heading": None, "heading_sigma_deg": None}
    assert stored == [{"width": 640, "height": 480, "scale": 1.0, "lens": None, **no_sensors}] * 2
    starter = json.loads(lines[3])
    assert abs(starter[0] - 522.2) < 10
    assert abs(starter[1] - 73.9) < 10
    assert (tmp_path / "answer.jpg").read_bytes().startswith(b"\xff\xd8\xff")
    assert len(lines) == 4  # DELETE answers 204: nothing printed


def test_the_readme_is_short_and_its_links_and_pictures_exist() -> None:
    text = README.read_text()
    assert len(text.splitlines()) <= 200
    targets = re.findall(r"\]\(([^)#]+)[^)]*\)", text)
    assert any(t.startswith("docs/screenshots/") for t in targets)
    for target in targets:
        assert (ROOT / target).exists(), target


def test_deploy_docs_list_every_setting_with_its_default() -> None:
    text = DEPLOY.read_text()
    for name, field in Settings.model_fields.items():
        row = re.search(rf"^\| `BUDDY_{name.upper()}` \| `([^`]*)` \|", text, re.M)
        assert row is not None, name
        assert row.group(1) == str(field.default), name
