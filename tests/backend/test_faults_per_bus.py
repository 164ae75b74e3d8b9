"""A node's fault history is its own bus's: node 1 of another bus (another server sharing the
data directory, a bus connected before) is another drive. GET …/faults lists the connected bus's
faults unless asked for every bus's (`all_buses=true`), each then naming its bus; a database
written before faults carried their bus keeps its rows (listed with every bus's)."""

from __future__ import annotations

import asyncio
import sqlite3
import time
from pathlib import Path
from typing import Any

from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings
from servodesk.storage import Storage
from servodesk.storage.migrations import MIGRATIONS

FAULT = {
    "time": time.time(),  # recent: older faults are pruned (events_max_days)
    "node": 1,
    "code": 4,
    "code_hex": "0x0004",
    "source": "vendor",
    "name_en": "Following error",
    "name_zh": "位置超差",
    "name_zh_source": "manual",
    "check": None,
    "check_zh": None,
    "error_register": None,
    "manufacturer_hex": None,
    "raw_hex": "0400",
    "state_before": "Operation enabled",
    "state_after": "Fault",
}


def other_servers_fault(data_dir: Path, **fields: Any) -> None:
    async def store() -> None:
        storage = Storage(data_dir, bus_of=lambda: "socketcan can7")
        await storage.start()
        storage.add_fault({**FAULT, **fields})
        await storage.close()

    asyncio.run(store())


def test_the_fault_history_is_this_buses_unless_asked(tmp_path: Path) -> None:
    other_servers_fault(tmp_path, name_en="Overcurrent")
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        mine = client.get("/api/nodes/1/faults").json()
        assert (mine["history"], mine["total"]) == ([], 0)
        every = client.get("/api/nodes/1/faults", params={"all_buses": True}).json()
        assert every["total"] == 1
        assert [(f["name_en"], f["bus"]) for f in every["history"]] == [
            ("Overcurrent", "socketcan can7")
        ]


def test_a_database_from_before_keeps_its_faults(tmp_path: Path) -> None:
    db = sqlite3.connect(tmp_path / "servodesk.sqlite")
    db.execute("CREATE TABLE schema_version (version INTEGER NOT NULL)")
    for version, sql in MIGRATIONS[:2]:  # as written before faults carried their bus
        db.executescript(f"BEGIN; {sql}; INSERT INTO schema_version VALUES ({version}); COMMIT;")
    # no such columns yet
    before = {k: v for k, v in FAULT.items() if k not in ("name_zh_source", "check_zh")}
    columns = ", ".join(f'"{c}"' for c in before)
    db.execute(
        f"INSERT INTO faults ({columns}) VALUES ({', '.join('?' * len(before))})",
        tuple(before.values()),
    )
    db.commit()
    db.close()

    async def read() -> tuple[list[dict[str, Any]], int]:
        storage = Storage(tmp_path, bus_of=lambda: "socketcan can0")
        await storage.start()
        try:
            assert (await storage.faults(1, 10, bus="socketcan can0")) == ([], 0)
            return await storage.faults(1, 10)
        finally:
            await storage.close()

    rows, total = asyncio.run(read())
    assert total == 1
    assert (rows[0]["name_en"], rows[0]["bus"]) == ("Following error", None)
    # stored before faults said where their Chinese came from: not known
    assert (rows[0]["name_zh"], rows[0]["name_zh_source"]) == ("位置超差", None)
    assert rows[0]["check_zh"] is None


def test_the_chinese_name_s_source_survives_a_restart(tmp_path: Path) -> None:
    kinco = {**FAULT, "code": 0x8611, "code_hex": "0x8611", "name_en": "Following error too high",
             "name_zh": "跟随误差过大", "name_zh_source": "translation"}  # fmt: skip
    other_servers_fault(tmp_path)  # MDi alarm 4: the manual's Chinese
    other_servers_fault(tmp_path, **kinco)

    async def read() -> list[dict[str, Any]]:
        storage = Storage(tmp_path)  # a new server: only the database remembers
        await storage.start()
        try:
            return (await storage.faults(1, 10))[0]
        finally:
            await storage.close()

    rows = asyncio.run(read())
    assert [(r["name_zh"], r["name_zh_source"]) for r in rows] == [
        ("跟随误差过大", "translation"),
        ("位置超差", "manual"),
    ]
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        history = client.get("/api/nodes/1/faults", params={"all_buses": True}).json()["history"]
    assert [(f["name_zh"], f["name_zh_source"]) for f in history] == [
        ("跟随误差过大", "translation"),
        ("位置超差", "manual"),
    ]


CHECK = (
    "Cause: 位置偏差计数器的数值超过设定值 — the position deviation counter exceeded the set value."
)
CHECK_ZH = "原因：位置偏差计数器的数值超过设定值。 来源：MDi-S1-C CANopen 手册 §4.1。"


def test_a_database_from_before_check_zh_reads_none(tmp_path: Path) -> None:
    # written by a server before faults carried check_zh (schema 5: name_zh_source, no check_zh)
    db = sqlite3.connect(tmp_path / "servodesk.sqlite")
    db.execute("CREATE TABLE schema_version (version INTEGER NOT NULL)")
    for version, sql in MIGRATIONS:
        if version > 5:
            break
        db.executescript(f"BEGIN; {sql}; INSERT INTO schema_version VALUES ({version}); COMMIT;")
    before = {k: v for k, v in FAULT.items() if k != "check_zh"} | {"check": CHECK}
    columns = ", ".join(f'"{c}"' for c in before)
    db.execute(
        f"INSERT INTO faults ({columns}) VALUES ({', '.join('?' * len(before))})",
        tuple(before.values()),
    )
    db.commit()
    db.close()

    async def read() -> list[dict[str, Any]]:
        storage = Storage(tmp_path)
        await storage.start()
        try:
            return (await storage.faults(1, 10))[0]
        finally:
            await storage.close()

    (row,) = asyncio.run(read())
    assert (row["check"], row["check_zh"], row["name_zh_source"]) == (CHECK, None, "manual")


def test_the_chinese_check_survives_a_restart(tmp_path: Path) -> None:
    other_servers_fault(tmp_path, check=CHECK, check_zh=CHECK_ZH)
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        history = client.get("/api/nodes/1/faults", params={"all_buses": True}).json()["history"]
    assert [(f["check"], f["check_zh"]) for f in history] == [(CHECK, CHECK_ZH)]
