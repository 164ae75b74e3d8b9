"""`servodesk` command line. The web app and field commands arrive with the backend core."""

from __future__ import annotations

import argparse
from collections.abc import Sequence

from servodesk import __version__


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="servodesk",
        description="Commissioning and diagnostics for CANopen servo drives. "
        "For simulated drives on a bus, run `servodesk-sim`.",
    )
    parser.add_argument("--version", action="version", version=f"servodesk {__version__}")
    parser.parse_args(argv)
    parser.print_help()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
