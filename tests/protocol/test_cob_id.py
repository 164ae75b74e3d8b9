"""COB-ID bases of the pre-defined connection set."""

from __future__ import annotations

import pytest

from servodesk_protocol import cob_id


@pytest.mark.parametrize(
    ("base", "node", "can_id"),
    [
        (cob_id.EMCY, 1, 0x081),
        (cob_id.TPDO1, 1, 0x181),
        (cob_id.RPDOS[3], 0x7F, 0x57F),
        (cob_id.SDO_TX, 5, 0x585),
        (cob_id.SDO_RX, 5, 0x605),
        (cob_id.HEARTBEAT, 127, 0x77F),
    ],
)
def test_for_node_and_split(base: int, node: int, can_id: int) -> None:
    assert cob_id.for_node(base, node) == can_id
    assert cob_id.split(can_id) == (base, node)


@pytest.mark.parametrize("node", [0, 128])
def test_for_node_refuses_ids_outside_1_to_127(node: int) -> None:
    with pytest.raises(ValueError, match=r"outside 1\.\.127"):
        cob_id.for_node(cob_id.SDO_RX, node)


def test_default_pdo_bases() -> None:
    assert cob_id.TPDOS == (0x180, 0x280, 0x380, 0x480)
    assert cob_id.RPDOS == (0x200, 0x300, 0x400, 0x500)


def test_node_services() -> None:
    assert cob_id.node_services(2) == {
        0x082: "EMCY",
        0x582: "SDO response",
        0x602: "SDO request",
        0x702: "heartbeat",
    }
