"""Print the app's OpenAPI schema as JSON: the one source of the phone app's API types.

``python -m backend.openapi > frontend/openapi.json``; the build turns it into TypeScript
(openapi-typescript), and a test fails when the committed types are stale.
"""

from __future__ import annotations

import json
import sys

from .main import create_app


def schema() -> str:
    """The schema as stable, indented JSON (keys sorted: a diff shows real changes)."""
    return json.dumps(create_app().openapi(), indent=2, sort_keys=True) + "\n"


if __name__ == "__main__":
    sys.stdout.write(schema())
