"""A quick stop that went out answers as a stop, even when the drive is too busy to answer the
reading of its state after it."""

from __future__ import annotations

from pathlib import Path

import can

from tests.backend.fault_rig import faulty_app

NODE = 3  # the CiA 402 drive
UPLOAD_ANSWER = 0x40  # SDO server command specifier 2 (upload response), bits 5-7


def an_upload_answer(msg: can.Message) -> bool:
    return msg.arbitration_id == 0x580 + NODE and msg.data[0] & 0xE0 == UPLOAD_ANSWER


def test_a_quick_stop_answers_200_when_the_state_after_it_is_not_read(tmp_path: Path) -> None:
    with faulty_app(tmp_path) as app:
        assert app.client.get(f"/api/nodes/{NODE}/drive").status_code == 200  # first contact
        rule = app.rig.drop("rx", an_upload_answer)  # writes are confirmed, reads go unanswered
        answer = app.client.post(f"/api/nodes/{NODE}/drive/quick-stop")
        app.rig.remove(rule)
        assert answer.status_code == 200, answer.text
        assert answer.json()["node"] == NODE
        state = app.client.get(f"/api/nodes/{NODE}/drive").json()["state"]
        assert state in ("quick_stop_active", "switch_on_disabled")  # the stop did go out
