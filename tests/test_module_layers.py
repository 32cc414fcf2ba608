"""Modules split by job import one way (issue 22): each imports only siblings before it.

The pinhole fit, the photos and the taps each went from one long module to several; a later import
back up the list (the fit's pose importing the fit, the intake importing the pictures made
from what it stores) would tie them into one again, and a cycle fails only at run time. A
module added to either folder must take its place in the order here.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
# Each folder's modules in order, those that others build on first.
LAYERS = {
    "shared_solver/estimation/pinhole": "pose predictions model propagation fit starts mistaps",
    "backend/photos": "lens gravity heading jpeg_rows exif intake pictures schemas kept repository"
    " service",
    # A phone's taps, the answer they give and the pictures drawn from both.
    "backend/taps": "photo_order schemas guidance problem shown repository answers service"
    " pictures",
}


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
    order = LAYERS[folder].split()
    modules = {path.stem: path for path in (ROOT / folder).glob("*.py") if path.stem != "__init__"}
    assert set(modules) == set(order), f"place every module of {folder} in LAYERS"
    for position, name in enumerate(order):
        later = sibling_imports(modules[name]) & set(order[position:])
        assert not later, f"{folder}/{name}.py imports {sorted(later)}, which come after it"
