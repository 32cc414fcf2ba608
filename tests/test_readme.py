"""The README's example runs and prints what the README says it prints."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

README = Path(__file__).parents[1] / "README.md"


def example() -> str:
    text = README.read_text()
    marker = text.index("<!-- example: solve")
    block = re.search(r"```python\n(.*?)```", text[marker:], re.S)
    assert block is not None
    return block.group(1)


def test_readme_example_prints_what_it_promises() -> None:
    output = io.StringIO()
    with contextlib.redirect_stdout(output):
        exec(compile(example(), "README.md", "exec"), {})  # our own README
    first, second = output.getvalue().splitlines()
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
