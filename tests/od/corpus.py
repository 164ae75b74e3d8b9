"""Where the test files live: the shared vendor corpus and the simulator's profile EDS files.

The vendor files are read in place from ../shared/eds (the repository's sibling) and never copied
into the project (see SOURCES.md there).
"""

from __future__ import annotations

from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
EDS_DIR = REPO / ".." / "shared" / "eds"
SUFFIXES = frozenset({".eds", ".dcf", ".xdd", ".xpd"})


def corpus_files() -> list[Path]:
    """Every EDS/DCF/XDD/XPD in the corpus, extensions matched case-insensitively (`.EDS`)."""
    if not EDS_DIR.is_dir():
        return []
    return sorted(p for p in EDS_DIR.iterdir() if p.suffix.lower() in SUFFIXES)


def corpus(name: str) -> Path:
    return EDS_DIR / name


def profile_eds_files() -> list[Path]:
    """The EDS files the simulator ships, one per drive profile."""
    return sorted((REPO / "sim" / "servodesk_data").glob("*/drive.eds"))
