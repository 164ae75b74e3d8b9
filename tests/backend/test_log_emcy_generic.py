"""CiA 301's generic emergency error codes (Table 21) decode by name, in a decoded log and in
the live fault decoder alike; a code no table lists keeps its most specific class."""

from __future__ import annotations

from pathlib import Path

import pytest

from servodesk.faults.decode import decode_emcy
from servodesk.logs import EventKind, LogAnalysis

GENERIC = {
    0x1000: "Generic error",
    0x2000: "Current – generic error",
    0x3000: "Voltage – generic error",
    0x4000: "Temperature – generic error",
    0x5000: "Device hardware – generic error",
    0x6000: "Device software – generic error",
    0x6100: "Internal software – generic",
    0x6200: "User software – generic",
    0x6300: "Data set – generic",
    0x7000: "Additional modules – generic error",
    0x8000: "Monitoring – generic error",
    0x8100: "Communication – generic",
    0x8130: "Life guard error or heartbeat error",
    0x8200: "Protocol error – generic",
    0x8250: "RPDO timeout",
    0x9000: "External error – generic error",
    0xF000: "Additional functions – generic error",
    0xFF00: "Device specific – generic error",
}


@pytest.mark.parametrize(("code", "words"), GENERIC.items())
def test_generic_codes_by_name(code: int, words: str) -> None:
    record = decode_emcy(None, 4, code.to_bytes(2, "little") + bytes([0x01, 0, 0, 0, 0, 0]))
    assert record.name_en == words
    assert record.source == "cia301"


def test_unlisted_code_keeps_its_most_specific_class() -> None:
    record = decode_emcy(None, 4, bytes.fromhex("0521010000000000"))
    assert record.name_en == "Unknown current, device input side code 0x2105"


def test_generic_codes_in_a_log(tmp_path: Path) -> None:
    log = tmp_path / "generic.log"
    lines = [
        f"({1700000000 + i / 10:.6f}) can0 084#{code & 0xFF:02X}{code >> 8:02X}01{'00' * 5}"
        for i, code in enumerate(GENERIC)
    ]
    log.write_text("\n".join(lines) + "\n")
    texts = [e.text for e in LogAnalysis(log).events() if e.kind == EventKind.EMCY]
    assert texts == [f"node 4 EMCY: 0x{c:04X} {w}" for c, w in GENERIC.items()]
    assert not [t for t in texts if "Unknown" in t]
