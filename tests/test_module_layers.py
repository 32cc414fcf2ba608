"""Modules split by job import one way (issue 22): each imports only siblings before it.

The pinhole fit and the photos each went from one long module to several; a later import
back up the list (the fit's pose importing the fit, the intake importing the pictures made
from what it stores) would tie them into one again, and a cycle fails only at run time. A
module added to either folder must take its place in the order here.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
# Each folder's modules, those that others build on first.
LAYERS = {
    "shared_solver/estimation/pinhole": [
        "pose",
        "predictions",
        "model",
        "propagation",
        "fit",
        "starts",
        "mistaps",
    ],
    "backend/photos": [
        "lens",
        "jpeg_rows",
        "exif",
        "intake",
        "pictures",
        "imaging",
        "schemas",
        "kept",
        "repository",
        "service",
    ],
}
# backend/photos/imaging.py re-exports pictures for the one module that others were changing
# when the split came; it must not gain users, and goes once that import moves.
OLD_NAME = "backend.photos.imaging"
OLD_NAME_USERS = {"backend/taps/service.py", "backend/photos/imaging.py"}


def sibling_imports(path: Path) -> set[str]:
    """The modules of ``path``'s own folder that it imports (``from .x import``,
    ``from . import x``)."""
    siblings = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module:
                siblings.add(node.module.split(".")[0])
            else:
                siblings.update(alias.name for alias in node.names)
    return siblings


@pytest.mark.parametrize("folder", sorted(LAYERS))
def test_each_module_imports_only_the_siblings_before_it(folder: str) -> None:
    order = LAYERS[folder]
    modules = {path.stem: path for path in (ROOT / folder).glob("*.py") if path.stem != "__init__"}
    assert set(modules) == set(order), f"place every module of {folder} in LAYERS"
    for position, name in enumerate(order):
        later = sibling_imports(modules[name]) & set(order[position:])
        assert not later, f"{folder}/{name}.py imports {sorted(later)}, which come after it"


def imports_old_name(path: Path) -> bool:
    """Whether ``path`` imports backend.photos.imaging, by its full or its relative name."""
    source = path.read_text()
    if "imaging" not in source:  # most files: no need to parse them
        return False
    in_photos = path.parent == ROOT / "backend" / "photos"
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import) and any(a.name == OLD_NAME for a in node.names):
            return True
        if isinstance(node, ast.ImportFrom):
            relative = in_photos and node.level == 1
            if node.module == OLD_NAME or (relative and node.module == "imaging"):
                return True
            if relative and not node.module and any(a.name == "imaging" for a in node.names):
                return True
    return False


def test_only_the_taps_service_still_imports_the_old_photo_module() -> None:
    packages = ("backend", "shared_solver", "testbed", "benchmarks", "deploy", "docsgen", "tests")
    users = {
        str(path.relative_to(ROOT))
        for package in packages
        for path in (ROOT / package).rglob("*.py")
        if imports_old_name(path)
    }
    assert users <= OLD_NAME_USERS
