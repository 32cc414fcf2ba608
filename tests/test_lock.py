"""The Python lock files say what pyproject.toml says: a dependency changed without
``make lock`` fails here, before a fresh machine installs something else."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
PIN = re.compile(r"^([A-Za-z0-9_.\-\[\]]+)==([^ ;\\]+)", re.M)


def locked(name: str) -> dict[str, str]:
    """Package -> version of one lock file, each entry with at least one hash."""
    text = (ROOT / "requirements" / name).read_text()
    entries = re.split(r"\n(?=\S)", text)
    pins: dict[str, str] = {}
    for entry in entries:
        match = PIN.match(entry)
        if match:
            assert "--hash=sha256:" in entry, entry.splitlines()[0]
            pins[canonicalize_name(match.group(1).split("[")[0])] = match.group(2)
    return pins


def pinned(specs: list[str]) -> dict[str, str]:
    out: dict[str, str] = {}
    for spec in specs:
        requirement = Requirement(spec)
        (version,) = [s.version for s in requirement.specifier if s.operator == "=="]
        out[canonicalize_name(requirement.name)] = version
    return out


def test_the_locks_hold_every_pin_of_pyproject_at_its_version() -> None:
    runtime, test = locked("runtime.txt"), locked("test.txt")
    for name, version in pinned(PROJECT["dependencies"]).items():
        assert runtime.get(name) == version, name
    for extra in PROJECT["optional-dependencies"].values():
        for name, version in pinned(extra).items():
            assert test.get(name) == version, name


def test_the_image_gets_the_versions_the_tests_ran_with() -> None:
    runtime, test = locked("runtime.txt"), locked("test.txt")
    assert runtime
    assert {name: test.get(name) for name in runtime} == runtime
