"""The field commands (`scan`, `read`, `write`, `dump`): the bus opened as the app opens it, one
request, a progress bar on stderr (imported only for these commands)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from typing import Any, TypeVar

from tqdm import tqdm

from servodesk.bus.config_check import check_bus_config
from servodesk.cli_args import bus_config
from servodesk.errors import ServodeskError
from servodesk.models.bus import BusState
from servodesk.services import Services, build_services
from servodesk.settings import Settings

T = TypeVar("T")


@asynccontextmanager
async def connected(args: argparse.Namespace) -> AsyncIterator[Services]:
    config = check_bus_config(bus_config(args))  # before anything starts
    # each command says which node it wants: no scan of its own after connecting
    services = build_services(Settings(auto_scan=False))
    try:
        status = await services.bus.connect(config)
        if status.state is not BusState.CONNECTED:
            raise ServodeskError(f"could not open the CAN bus: {status.error}")
        yield services
    finally:
        await services.close()


async def field_command(args: argparse.Namespace) -> int:
    async with connected(args) as services:
        registry = services.registry
        if args.command == "scan":
            result = await _with_spinner(
                "scanning", registry.scan(sdo_sweep=True, timeout_ms=args.timeout_ms)
            )
            print(f"{'node':>4}  {'state':<16} {'profile':<15} name")
            for node in result.nodes:
                print(
                    f"{node.node:>4}  {node.nmt_state.value:<16} {node.profile:<15} "
                    f"{node.name or ''}"
                )
            print(f"{len(result.nodes)} node(s) in {result.duration_ms} ms", file=sys.stderr)
            return 0
        await registry.add(args.node)
        if args.command == "read":
            value = await services.sdo.read(args.node, args.index, args.sub)
            print(value.text)
            return 0
        if args.command == "write":
            # typed at the terminal by the user it acts as: that is the confirmation
            written = await services.sdo.write(
                args.node, args.index, args.sub, args.value, size=args.size, confirm=True
            )
            print(written.text)
            return 0
        if args.command == "dump":
            text = await _with_progress(
                f"reading node {args.node}",
                lambda progress: services.paramsets.export_dcf(args.node, progress=progress),
            )
            sys.stdout.write(text)
            return 0
    return 2


async def _with_spinner(label: str, work: Awaitable[T]) -> T:
    with tqdm(desc=label, bar_format="{desc}: {elapsed}", file=sys.stderr, leave=False):
        return await work


async def _with_progress(
    label: str, start: Callable[[Callable[[int, int], None]], Awaitable[T]]
) -> T:
    """A progress bar on stderr for work that reports (done, total)."""
    bar: Any = tqdm(desc=label, unit="entry", file=sys.stderr, leave=False)

    def progress(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh()

    try:
        return await start(progress)
    finally:
        bar.close()
