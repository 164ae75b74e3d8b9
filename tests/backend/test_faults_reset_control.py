"""The fault routes respect who controls the drive (as /drive/fault-reset does), and an MDi
alarm (a 2-byte EMCY) leaves no error in the server log."""

from __future__ import annotations

import logging
import time

import pytest
from fastapi.testclient import TestClient

ALICE = {"X-Client-Id": "page-a", "X-Client-Name": "Alice"}
BOB = {"X-Client-Id": "page-b", "X-Client-Name": "Bob"}


def test_fault_reset_of_a_drive_another_page_controls_is_refused(client: TestClient) -> None:
    taken = client.post("/api/nodes/3/drive/controller", headers=ALICE, json={})
    assert taken.status_code == 200, taken.text
    refused = client.post("/api/nodes/3/faults/reset", headers=BOB)
    assert refused.status_code == 409
    assert refused.json()["error"] == "held_by_other"
    assert "Alice" in refused.json()["message"]
    assert client.post("/api/nodes/3/faults/reset").status_code == 409  # a script, too
    mine = client.post("/api/nodes/3/faults/reset", headers=ALICE)
    assert mine.status_code == 200, mine.text
    # a drive nobody controls: anyone may reset it, as before
    assert client.post("/api/nodes/2/faults/reset").status_code == 200


def test_mdi_alarm_logs_no_error(client: TestClient, caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG)
    assert client.put("/api/nodes/1/sdo/5FF0/0", json={"value": 4}).status_code == 200
    for _ in range(500):
        if client.get("/api/nodes/1/faults?limit=1").json()["active"] is not None:
            break
        time.sleep(0.01)
    else:
        raise AssertionError("the alarm did not arrive")
    errors = [r for r in caplog.records if r.levelno >= logging.ERROR]
    assert errors == [], [r.getMessage() for r in errors]
