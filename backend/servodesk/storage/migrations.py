"""The schema, versioned: `schema_version` holds the version reached; each migration runs once,
in order, in its own transaction. Add new tables (the audit log of the Trust issue) as the next
migration; never edit one that shipped."""

from __future__ import annotations

import sqlite3

MIGRATIONS: tuple[tuple[int, str], ...] = (
    (
        1,
        """
        CREATE TABLE events (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            time REAL NOT NULL,
            kind TEXT NOT NULL,
            node INTEGER,
            message TEXT NOT NULL,
            data TEXT NOT NULL DEFAULT '{}'
        );
        CREATE INDEX events_node ON events (node, id);
        CREATE INDEX events_kind ON events (kind, id);
        CREATE INDEX events_time ON events (time);
        CREATE TABLE faults (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            time REAL NOT NULL,
            node INTEGER NOT NULL,
            code INTEGER NOT NULL,
            code_hex TEXT NOT NULL,
            source TEXT NOT NULL,
            name_en TEXT NOT NULL,
            name_zh TEXT,
            "check" TEXT,
            error_register INTEGER,
            manufacturer_hex TEXT,
            raw_hex TEXT NOT NULL,
            state_before TEXT,
            state_after TEXT
        );
        CREATE INDEX faults_node ON faults (node, id);
        CREATE INDEX faults_time ON faults (time);
        """,
    ),
    (
        2,
        # the bus an event came from ("socketcan can0", "virtual servodesk-sim-…"): two servers
        # sharing a data directory each show their own bus's timeline
        """
        ALTER TABLE events ADD COLUMN bus TEXT;
        CREATE INDEX events_bus ON events (bus, id);
        """,
    ),
    (
        3,
        # the bus a fault came from, as for events: a node's fault history is its own bus's
        """
        ALTER TABLE faults ADD COLUMN bus TEXT;
        CREATE INDEX faults_bus ON faults (bus, node, id);
        """,
    ),
    (
        4,
        # commissioning records (servodesk.commissioning): one row per axis's record, the
        # record itself as JSON (its steps change shape as steps are automated), node and time
        # as columns for the list and its filter
        """
        CREATE TABLE commissioning (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            node INTEGER NOT NULL,
            created REAL NOT NULL,
            record TEXT NOT NULL
        );
        CREATE INDEX commissioning_node ON commissioning (node, id);
        """,
    ),
    (
        5,
        # where a fault's Chinese name comes from: "manual" (the drive manual's own, MDi-S1-C)
        # or "translation" (ServoDesk's, of an English source); NULL for rows stored before
        """
        ALTER TABLE faults ADD COLUMN name_zh_source TEXT;
        """,
    ),
    (
        6,
        # an event's words as a message id and its parameters (JSON), for the page's catalogue
        # (servodesk.events.texts); NULL for events stored before, and for English-only words
        """
        ALTER TABLE events ADD COLUMN message_id TEXT;
        ALTER TABLE events ADD COLUMN params TEXT;
        """,
    ),
    (
        7,
        # a fault's cause and what to check in Chinese (the API's `check_zh`, beside `check`);
        # NULL for rows stored before
        """
        ALTER TABLE faults ADD COLUMN check_zh TEXT;
        """,
    ),
)
LATEST = MIGRATIONS[-1][0]


def migrate(db: sqlite3.Connection) -> int:
    """Bring `db` to the latest schema; returns the version it had before."""
    db.execute("CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL)")
    row = db.execute("SELECT MAX(version) FROM schema_version").fetchone()
    before = int(row[0]) if row and row[0] is not None else 0
    for version, sql in MIGRATIONS:
        if version <= before:
            continue
        # executescript commits first; the BEGIN makes each migration all-or-nothing
        db.executescript(
            f"BEGIN; {sql}; INSERT INTO schema_version (version) VALUES ({version}); COMMIT;"
        )
    return before
