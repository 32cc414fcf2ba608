"""One source for what the phone and the server share: the palette (#3 is the same colour on
both phones and in the server's drawings) and the limits (photo side, landmark count and
numbers, code length, event names, tap precision). Python, TypeScript and CSS read the same
two files; none keeps a copy. The values the app reads are checked in vitest
(frontend/src/palette.test.ts, limits.test.ts); here, that each reader reads the file."""

from __future__ import annotations

import json
import re
from pathlib import Path

from backend import limits
from shared_solver.drawing import palette

ROOT = Path(__file__).parents[1]
APP = ROOT / "frontend" / "src"
PALETTE_JSON = ROOT / "shared_solver" / "drawing" / "palette.json"
LIMITS_JSON = ROOT / "backend" / "limits.json"


def imports(module: Path) -> list[Path]:
    """The files a TypeScript module imports by relative path, resolved."""
    found = re.findall(r"""^import [^;]*?from\s+"(\.[^"?]+)""", module.read_text(), re.M)
    return [(module.parent / name).resolve() for name in found]


def app_sources() -> list[Path]:
    """The app's own modules and stylesheet (not its tests, not the generated API types)."""
    files = [*APP.rglob("*.ts"), *APP.rglob("*.tsx"), *APP.rglob("*.css")]
    return [f for f in files if ".test." not in f.name and "generated" not in f.parts]


def test_python_reads_the_palette_file() -> None:
    source = json.loads(PALETTE_JSON.read_text())
    assert tuple(c["hex"] for c in source["landmarks"]) == palette.LANDMARK_COLOURS_HEX
    assert source["friend"] == palette.FRIEND_COLOUR_HEX
    assert source["suspect"] == palette.SUSPECT_COLOUR_HEX
    assert source["outline"] == palette.OUTLINE_COLOUR_HEX


def test_the_app_reads_the_palette_file_and_keeps_no_copy() -> None:
    assert PALETTE_JSON.resolve() in imports(APP / "palette.ts")
    source = json.loads(PALETTE_JSON.read_text())
    colours = {c["hex"].lower() for c in source["landmarks"]}
    colours |= {source[key].lower() for key in ("friend", "suspect", "outline")}
    colours -= {"#ffffff"}  # landmark 10's white is also every interface's white
    for module in app_sources():
        text = module.read_text().lower()
        copied = sorted(c for c in colours if c in text)
        assert copied == [], f"{module.relative_to(ROOT)} copies palette colours {copied}"


def test_the_css_paints_with_the_palettes_custom_properties() -> None:
    """styles.css uses --friend, --suspect and --outline, which palette.ts sets on the page
    from the palette file, and defines none of them itself."""
    css = (APP / "styles.css").read_text()
    setter = (APP / "palette.ts").read_text()
    for name in ("--friend", "--suspect", "--outline"):
        assert f"var({name})" in css
        assert not re.search(rf"^\s*{name}\s*:", css, re.M), f"styles.css defines {name}"
        assert f'"{name}"' in setter
    assert "applyPalette(document.documentElement.style)" in (APP / "main.tsx").read_text()


def test_python_and_the_app_read_the_limits_file() -> None:
    source = json.loads(LIMITS_JSON.read_text())
    assert source["stored_photo_side"] == limits.STORED_PHOTO_SIDE
    assert source["max_landmarks"] == limits.MAX_LANDMARKS
    assert source["max_landmark_id"] == limits.MAX_LANDMARK_ID
    assert source["join_code_length"] == limits.JOIN_CODE_LENGTH
    assert list(limits.EVENTS) == source["events"]
    assert LIMITS_JSON.resolve() in imports(APP / "limits.ts")
    # Every module that needs a shared limit takes it from limits.ts.
    for module, names in {
        "downscale.ts": ["STORED_PHOTO_SIDE"],
        "landmarks.ts": ["MAX_LANDMARKS", "MAX_LANDMARK_ID"],
        "routes.ts": ["CODE_DIGITS"],
        "reconnect.ts": ["EVENTS"],
        "precision.ts": ["TAP_PRECISION"],
    }.items():
        assert (APP / "limits").resolve() in imports(APP / module), module
        text = (APP / module).read_text()
        for name in names:
            assert not re.search(rf"const {name}\b", text), f"{module} defines its own {name}"
