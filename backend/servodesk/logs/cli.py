"""`servodesk decode-log FILE [--dcf FILE] [--profile N=NAME] [--format FMT] [-o OUT]`.

The summary comes first, yet the events stream: they are written to a temporary file while
the log is decoded (flat memory), then copied out after the summary. Where the summary goes:
- events on stdout: text -> summary lines, a blank line, the events; json -> a first line
  {"summary": [...], "stats": {...}}; csv -> the summary on stderr (the CSV stays clean);
- events in a file (-o): the summary on stdout.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any, TextIO

from tqdm import tqdm

from servodesk.logs.analysis import LogAnalysis
from servodesk.logs.context import parse_profiles
from servodesk.logs.export import ExportFormat, ParquetWriter, text_writer, write_all
from servodesk.logs.reader import LogFormatError
from servodesk.od import OdImportError


def _fail(message: str) -> int:
    print(f"servodesk: {message}", file=sys.stderr)
    return 1


def decode_log(args: argparse.Namespace) -> int:
    path = Path(args.file)
    fmt = ExportFormat(args.format)
    output = Path(args.output) if args.output else None
    if fmt is ExportFormat.PARQUET and output is None:
        return _fail("--format parquet writes a file: give it with -o OUT")
    if not path.is_file():
        return _fail(f"{path}: no such file")
    dcf = Path(args.dcf) if args.dcf else None
    try:
        profiles = parse_profiles(getattr(args, "profile", None))
    except ValueError as error:
        return _fail(f"--profile {error}")
    try:
        analysis = LogAnalysis(path, dcf=dcf, bitrate=args.bitrate, profiles=profiles)
    except (OdImportError, OSError) as error:
        return _fail(f"{dcf}: {error}")
    bar: Any = tqdm(
        total=path.stat().st_size, unit="B", unit_scale=True, desc=path.name,
        file=sys.stderr, leave=False,
    )  # fmt: skip

    def progress(done: int) -> None:
        bar.update(done - bar.n)

    try:
        if fmt is ExportFormat.PARQUET:
            assert output is not None
            write_all(ParquetWriter(output), analysis.events(progress))
            bar.close()
            _summary_lines(analysis, sys.stdout)
            return 0
        with tempfile.TemporaryFile("w+", encoding="utf-8") as spool:
            write_all(text_writer(fmt, spool), analysis.events(progress))
            bar.close()
            spool.seek(0)
            if output is not None:
                with output.open("w", encoding="utf-8", newline="") as out:
                    shutil.copyfileobj(spool, out)
                _summary_lines(analysis, sys.stdout)
            else:
                _summary_first(analysis, fmt)
                shutil.copyfileobj(spool, sys.stdout)
    except LogFormatError as error:
        bar.close()  # the message gets a line of its own
        return _fail(str(error))
    except (OSError, ValueError) as error:
        # python-can readers raise ValueError on a line they cannot parse
        bar.close()
        return _fail(f"{path}: cannot read the log: {error}")
    finally:
        bar.close()
    return 0


def _summary_lines(analysis: LogAnalysis, out: TextIO) -> None:
    for line in analysis.summary():
        out.write(line + "\n")


def _summary_first(analysis: LogAnalysis, fmt: ExportFormat) -> None:
    if fmt is ExportFormat.JSON:
        head = {"summary": analysis.summary(), "stats": analysis.stats()}
        sys.stdout.write(json.dumps(head, ensure_ascii=False) + "\n")
    elif fmt is ExportFormat.CSV:
        _summary_lines(analysis, sys.stderr)
    else:
        _summary_lines(analysis, sys.stdout)
        sys.stdout.write("\n")
