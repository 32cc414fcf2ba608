"""Print the app's OpenAPI schema as JSON: the one source of the phone app's API types.

The build (``make``) pipes it into openapi-typescript, which writes
``frontend/src/generated/openapi.ts``; tests/test_api_types.py fails when the committed
types are stale.
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
