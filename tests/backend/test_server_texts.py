"""The server's texts by id (enable reasons, timeline words, SDO abort meanings) and the page's
English `server` catalogue are the same words, so a text reads the same whether the page shows
the server's message or its catalogue's; the Chinese catalogue has every id with the same
placeholders."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from servodesk.errors import (
    ERROR_TEXTS,
    CommTimeoutError,
    NodeStoppedError,
    SdoProtocolError,
    ServodeskError,
)
from servodesk.events.texts import EVENT_TEXTS, say
from servodesk.motion.axis import travel_info
from servodesk.motion.drive_io import Travel
from servodesk.motion.explain import Observed, explain
from servodesk.motion.reason_texts import REASON_TEXTS, reason
from servodesk.motion.stop_reasons import STOP_TEXTS, Reason, nested, nested_stop, said, then
from servodesk.motion.units import DriveUnits
from servodesk.motion.words import TRANSITION_TEXTS
from servodesk.pdo_problems import PDO_TEXTS, Owner, owner_params, problem
from servodesk.profiles.match import LABELS
from servodesk_protocol import sdo_abort
from servodesk_protocol.cia402 import Cia402State
from servodesk_protocol.cob_id import node_services
from servodesk_protocol.pdo import RESTRICTED_CAN_IDS

LOCALES = Path(__file__).parents[2] / "frontend" / "src" / "i18n" / "locales"
PLACEHOLDER = re.compile(r"\{\{(\w+)\}\}")


def catalogue(language: str) -> dict[str, str]:
    tree = json.loads((LOCALES / f"server.{language}.json").read_text(encoding="utf-8"))
    return {
        f"{area}.{name}": text
        for area, texts in tree["server"].items()
        for name, text in texts.items()
    }


# every text the server says by id: the reasons, the timeline's words, the SDO aborts' meanings
SERVER_TEXTS = {
    **REASON_TEXTS,
    **EVENT_TEXTS,
    **ERROR_TEXTS,
    **TRANSITION_TEXTS,
    **STOP_TEXTS,
    **PDO_TEXTS,
    # the fixed words the server sends as parameters (a service, a CiA 301 reserved range)
    **{
        f"word.{re.sub(r'[^a-z0-9]+', '_', word.lower()).strip('_')}": word
        for word in [*node_services(1).values(), *(use for _, _, use in RESTRICTED_CAN_IDS)]
    },
    **{f"abort.{code:08X}": meaning for code, meaning in sdo_abort.MEANINGS.items()},
}


def test_the_english_catalogue_is_the_servers_words() -> None:
    english = {key: PLACEHOLDER.sub(r"{\1}", text) for key, text in catalogue("en").items()}
    assert english == SERVER_TEXTS


def test_the_chinese_catalogue_has_every_id_and_placeholder() -> None:
    chinese = catalogue("zh-CN")
    assert chinese.keys() == SERVER_TEXTS.keys()
    for key, template in SERVER_TEXTS.items():
        assert set(PLACEHOLDER.findall(chinese[key])) == set(re.findall(r"\{(\w+)\}", template))
        # a text of words has Chinese; one of parameters only ("{was} → {state}") or a name
        # ("SYNC", "EMCY") has none
        assert re.search(r"[\u4e00-\u9fff]", chinese[key]) or not re.search(
            r"[a-z]{2,}", PLACEHOLDER.sub("", chinese[key])
        ), key


@pytest.mark.parametrize(
    ("seen", "ids"),
    [
        (Observed(statusword=None, controlword=None, nmt_state="stopped"), ["reason.nmt_stopped"]),
        (
            Observed(statusword=None, controlword=None, nmt_state="operational"),
            ["reason.no_answer"],
        ),
        (
            Observed(statusword=0x0008, controlword=0x0080, nmt_state="operational"),
            ["reason.fault_unknown", "reason.fault_reset_high", "reason.voltage_disabled"],
        ),
        (
            Observed(
                statusword=0x0231,
                controlword=0x0106,
                nmt_state="pre-operational",
                mode=7,
                supported=frozenset({1, 3}),
                needs_pdos=True,
                held_by="alice",
            ),
            [
                "reason.nmt_not_operational",
                "reason.held_elsewhere",
                "reason.mode_not_in_6502",
                "reason.halt_set",
            ],
        ),
        (
            Observed(statusword=0x0231, controlword=0x0006, nmt_state="operational"),
            ["reason.stayed"],
        ),
    ],
)
def test_each_reason_carries_its_id_and_the_words_it_makes(seen: Observed, ids: list[str]) -> None:
    reasons = explain(seen)
    assert [r.message_id for r in reasons] == ids
    for r in reasons:
        assert r.message_id is not None
        assert r.message == REASON_TEXTS[r.message_id].format(**r.params)


def test_a_reason_keeps_the_english_it_always_had() -> None:
    held = reason("held_by_other", "reason.held_elsewhere", holder="alice (operator)")
    assert held.message == "alice (operator) controls this axis now"
    seen = Observed(
        statusword=0x0237,
        controlword=0x000F,
        nmt_state="operational",
        mode=1,
        mode_display=0,
        target=Cia402State.OPERATION_ENABLED,
    )
    assert [r.message for r in explain(seen)] == [
        "6060h asks for Profile position (PP) but 6061h shows 0: the drive runs no mode (an "
        "unsupported value, MDi-S1-C CANopen manual §3.3)"
    ]


@pytest.mark.parametrize(
    ("message_id", "params", "english"),
    [
        ("event.bus_connected", {"where": "virtual sim"}, "bus connected (virtual sim)"),
        ("event.nmt_sent", {"nmt_command": "start", "node": 2}, "NMT start sent to node 2"),
        ("event.state", {"node": 1, "state": "Fault"}, "node 1: Fault"),
    ],
)
def test_an_event_says_its_english_from_its_id(
    message_id: str, params: dict[str, str | int], english: str
) -> None:
    said = say(message_id, **params)
    assert (said.message, said.message_id, dict(said.params)) == (english, message_id, params)


def test_an_event_id_said_without_its_parameters_fails_where_it_is_said() -> None:
    with pytest.raises(KeyError):
        say("event.nmt_sent", node=2)


@pytest.mark.parametrize(
    ("error", "message_id", "params"),
    [
        (
            CommTimeoutError(3, "read 6041h:00h"),
            "error.no_answer_read",
            {"node": 3, "where": "6041h:00h"},
        ),
        (NodeStoppedError(2), "error.node_stopped", {"node": 2}),
        # words that are not the session's own exchange, or a cause in English: no id
        (CommTimeoutError(3, "reading its entries (stopped after 4)"), None, {}),
        (
            SdoProtocolError(3, "read 6041h:00h", "toggle bit"),
            None,
            {"node": 3, "where": "6041h:00h"},
        ),
    ],
)
def test_an_error_says_its_words_by_id_only_when_they_are_the_catalogues(
    error: ServodeskError, message_id: str | None, params: dict[str, str | int]
) -> None:
    said_id, said_params = error.said()
    assert said_id == message_id
    if message_id is not None:
        assert said_params == params
        assert str(error) == ERROR_TEXTS[message_id].format(**params)


def test_the_pages_travel_words_are_the_servers() -> None:
    """The Drive page says the travel rows' fixed source and note in its own language; in
    English they are the server's words (servodesk.motion.axis.travel_info)."""
    travel = json.loads((LOCALES / "drive.en.json").read_text(encoding="utf-8"))["drive"]["travel"]
    info = travel_info(Travel(switches=(-1, 1), software_limit=(0, 0)), DriveUnits())
    assert info.switches is not None
    assert info.software_limit is not None
    assert (travel["switchesSource"], travel["switchesNote"]) == (
        info.switches.source,
        info.switches.note,
    )
    assert (travel["softwareLimitSource"], travel["softwareLimitOff"]) == (
        info.software_limit.source,
        info.software_limit.note,
    )


def test_the_pages_profile_labels_are_the_servers() -> None:
    """The page names a shipped profile in its own language by the profile's key; in English
    as the server labels it (servodesk.profiles.match)."""
    tree = json.loads((LOCALES / "en.json").read_text(encoding="utf-8"))
    assert tree["format"]["profile"] == LABELS


def test_a_stop_reason_is_its_english_words_and_knows_its_id() -> None:
    first = Reason("stop.keepalive", ms=300)
    assert first == "keep-alive missed for 300 ms"
    assert said(first) == ("stop.keepalive", {"ms": 300})
    later = then(first, "stop.then_unread", error="no answer")
    assert later == (
        "keep-alive missed for 300 ms; the speed could not be read while stopping (no answer)"
    )
    assert said(later) == (
        "stop.then_unread",
        {
            "reason": "keep-alive missed for 300 ms",
            "reason_id": "stop.keepalive",
            "reason_ms": 300,
            "error": "no answer",
        },
    )
    assert said("a plain reason") == (None, {})
    stored = nested_stop("quick stop", "stop.quick_stop", {})
    assert stored == nested("reason", Reason("stop.quick_stop"))


def test_a_pdo_problem_names_who_uses_the_can_id_by_id_too() -> None:
    owner = Owner("owner.node_service", node=2, service="EMCY")
    assert owner == "node 2 EMCY"
    found = problem(
        "tpdo", 1, "pdo.can_id_used", 0x1800, 1, pdo="TPDO1", can_id="82", **owner_params(owner)
    )
    assert found.message == "TPDO1 CAN id 82h is already used by node 2 EMCY"
    assert (found.message_id, found.params) == (
        "pdo.can_id_used",
        {
            "pdo": "TPDO1",
            "can_id": "82",
            "owner": "node 2 EMCY",
            "owner_id": "owner.node_service",
            "owner_node": 2,
            "owner_service": "EMCY",
        },
    )
    assert owner_params("SYNC") == {"owner": "SYNC"}  # words without an id: shown as sent
