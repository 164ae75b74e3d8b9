"""The live check as an engineer reads it: bit fields in hex, scaled units converted, and what
the Drive page does with the node's RPDOs (said from the routes the motion service takes)."""

from __future__ import annotations

import re
import time
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.pdo.display import display_text, unit_scale
from servodesk.pdo.drive_use import drive_page_use
from servodesk.pdo.model import MappedObject, PdoConfig
from tests.backend.test_api_routes import ok, wait_for

CONTROLWORD = MappedObject(0x6040, 0, 16)  # Controlword
TARGET_POSITION = MappedObject(0x607A, 0, 32)  # Target position
IP_SETPOINT = MappedObject(0x60C1, 1, 32)  # Interpolation data record: set-point


@pytest.mark.parametrize(
    ("args", "shown"),
    [
        ((0x6041, 0, "Statusword", 592, 16, ""), "0x0250"),
        ((0x6040, 0, "Controlword", 0x0F, 16, ""), "0x000F"),
        ((0x2010, 0, "Status word 2", 5, 16, ""), "0x0005"),  # a vendor's bit field
        ((0x1001, 0, "Error register", 0x81, 8, ""), "0x81"),
        ((0x6077, 0, "Torque actual value", 0, 16, "0.1 %"), "0.0 %"),
        ((0x6077, 0, "Torque actual value", -125, 16, "0.1 %"), "-12.5 %"),
        ((0x606C, 0, "Velocity actual value", 1200, 32, "rpm"), "1200 rpm"),
        ((0x6064, 0, "Position actual value", -3, 32, ""), "-3"),
        ((0x2000, 1, "Flag", True, 1, ""), "true"),
    ],
)
def test_display(args: tuple[Any, ...], shown: str) -> None:
    assert display_text(*args) == shown


def test_unit_scale() -> None:
    assert unit_scale("0.1 %") == (0.1, "%", 1)
    assert unit_scale("0.1 %/ms") == (0.1, "%/ms", 1)
    assert unit_scale("100 us") == (100.0, "us", 0)
    assert unit_scale("user units/s") == (1.0, "user units/s", 0)


def rpdo(number: int, transmission: int, *mapping: MappedObject) -> PdoConfig:
    return PdoConfig("rpdo", number, 0x200 + number * 0x100, True, transmission, mapping=mapping)


def test_drive_page_sends_commands_in_event_driven_rpdos() -> None:
    text = drive_page_use([rpdo(1, 255, CONTROLWORD, TARGET_POSITION)])
    assert text is not None
    assert text.startswith("The Drive page sends its commands by RPDO:")
    assert "6040h controlword, 607Ah target position in RPDO1" in text


def test_drive_page_leaves_synchronous_rpdos_to_sync() -> None:
    text = drive_page_use(
        [rpdo(1, 1, CONTROLWORD, TARGET_POSITION), rpdo(4, 1, CONTROLWORD, IP_SETPOINT)]
    )
    assert text is not None
    assert text.startswith("The Drive page does not send its commands in these RPDOs")
    assert "RPDO1, RPDO4 are synchronous" in text
    assert "set-points (60C1h:01) in RPDO4, taken at SYNC" in text
    assert drive_page_use([PdoConfig("rpdo", 1, 0x201, False, 255)]) is None


def test_live_check_shows_hex_statusword_and_scaled_torque(client: TestClient) -> None:
    wanted = ok(client.get("/api/nodes/3/pdos/recommended", params={"modes": "pp,pt"}))["pdos"]
    ok(client.put("/api/nodes/3/pdos", json={"pdos": wanted}))
    ok(client.post("/api/nodes/3/nmt", json={"command": "start"}))
    started = ok(client.post("/api/nodes/3/pdos/live"))
    assert started["drive_page"].startswith("The Drive page sends its commands by RPDO")

    def values() -> dict[int, dict[str, Any]]:
        rows = ok(client.get("/api/nodes/3/pdos/live"))["pdos"]
        return {v["index"]: v for row in rows if row["kind"] == "tpdo" for v in row["values"]}

    assert wait_for(lambda: {0x6041, 0x6077} <= values().keys())
    time.sleep(0.1)
    seen = values()
    assert re.fullmatch(r"0x[0-9A-F]{4}", seen[0x6041]["display"])
    assert int(seen[0x6041]["display"], 16) == seen[0x6041]["value"]
    assert seen[0x6077]["unit"] == "0.1 %"  # the dictionary's unit, as before
    assert re.fullmatch(r"-?\d+\.\d %", seen[0x6077]["display"])
    ok(client.delete("/api/nodes/3/pdos/live"))
