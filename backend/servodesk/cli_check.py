"""`servodesk check-record BUNDLE.zip`: the field check of commissioning/check.py from the
command line, on any PC: the bundle holds the hand-over (record, DCF, audit CSV), the bus the
drive as it is now; the server's database is not used (imported only for this command)."""

from __future__ import annotations

import argparse
import asyncio
import sys

from servodesk.cli_field import connected
from servodesk.commissioning.check import FieldCheck, HandOver, open_bundle
from servodesk.commissioning.check_core import summary_lines
from servodesk.errors import ServodeskError

SAME, DIFFERS = 0, 1


def _open(path: str) -> HandOver:
    try:
        with open(path, "rb") as file:
            return open_bundle(file)
    except OSError as error:
        raise ServodeskError(f"{path}: {error.strerror or error}") from None
    except ServodeskError as error:
        raise ServodeskError(f"{path}: {error}") from None


async def check_record(args: argparse.Namespace) -> int:
    hand_over = await asyncio.to_thread(_open, args.bundle)  # before the bus is opened
    node = args.node or hand_over.record.node
    async with connected(args) as services:
        await services.registry.add(node)
        check = FieldCheck(
            services.registry, services.od_parser, services.faults, audit=None, history=False
        )
        result = await check.run(hand_over, node)
    if args.json:
        print(result.model_dump_json(indent=2))
    else:
        print("\n".join(summary_lines(result)))
    sys.stdout.flush()
    return DIFFERS if result.differs else SAME
