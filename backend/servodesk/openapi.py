"""Print the OpenAPI schema (the frontend's TypeScript client is generated from it):
`python -m servodesk.openapi > frontend/openapi.json`."""

from __future__ import annotations

import json
import sys

from servodesk.app import create_app


def main() -> int:
    schema = create_app(static_dir=None).openapi()
    json.dump(schema, sys.stdout, indent=2, sort_keys=True)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
