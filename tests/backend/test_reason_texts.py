"""The reasons' English templates and the page's English `server` catalogue are the same words,
so a reason reads the same whether the page shows the server's message or its catalogue's; the
Chinese catalogue has every id with the same placeholders."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from servodesk.motion.explain import Observed, explain
from servodesk.motion.reason_texts import REASON_TEXTS, reason
from servodesk_protocol.cia402 import Cia402State

LOCALES = Path(__file__).parents[2] / "frontend" / "src" / "i18n" / "locales"
PLACEHOLDER = re.compile(r"\{\{(\w+)\}\}")


def catalogue(language: str) -> dict[str, str]:
    tree = json.loads((LOCALES / f"server.{language}.json").read_text(encoding="utf-8"))
    return {
        f"{area}.{name}": text
        for area, texts in tree["server"].items()
        for name, text in texts.items()
    }


def test_the_english_catalogue_is_the_servers_words() -> None:
    english = {key: PLACEHOLDER.sub(r"{\1}", text) for key, text in catalogue("en").items()}
    assert english == dict(REASON_TEXTS)


def test_the_chinese_catalogue_has_every_id_and_placeholder() -> None:
    chinese = catalogue("zh-CN")
    assert chinese.keys() == REASON_TEXTS.keys()
    for key, template in REASON_TEXTS.items():
        assert set(PLACEHOLDER.findall(chinese[key])) == set(re.findall(r"\{(\w+)\}", template))
        assert re.search(r"[\u4e00-\u9fff]", chinese[key]), key


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
