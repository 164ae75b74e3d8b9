"""The safe write order of a parameter set (pure, table-tested)."""

from __future__ import annotations

import pytest

from servodesk.od import DataType, OdSub
from servodesk.od.model import Access, Value
from servodesk.params.dcf_order import Write, plan_writes, skip_reason

Step = tuple[int, int, Value, bool]  # index, sub-index, value, final


def steps(values: dict[tuple[int, int], Value]) -> list[Step]:
    return [(w.index, w.subindex, w.value, w.final) for w in plan_writes(values)]


TPDO1 = {
    (0x1800, 1): 0x40000183,  # TPDO1 COB-ID
    (0x1800, 2): 0xFF,  # transmission type
    (0x1800, 5): 20,  # event timer
    (0x1A00, 0): 2,  # TPDO1 mapping: number of entries
    (0x1A00, 1): 0x60410010,  # Statusword
    (0x1A00, 2): 0x60610008,  # Modes of operation display
}


@pytest.mark.parametrize(
    ("values", "expected"),
    [
        pytest.param(
            TPDO1,
            [
                (0x1800, 1, 0xC0000183, False),  # invalid first
                (0x1A00, 0, 0, False),  # mapping cleared
                (0x1A00, 1, 0x60410010, True),
                (0x1A00, 2, 0x60610008, True),
                (0x1A00, 0, 2, True),  # count after its entries
                (0x1800, 2, 0xFF, True),  # other comm parameters while still invalid
                (0x1800, 5, 20, True),
                (0x1800, 1, 0x40000183, True),  # the file's COB-ID last
            ],
            id="tpdo-unit",
        ),
        pytest.param(
            {(0x1600, 1): 0x60400010, (0x1600, 0): 1},
            [(0x1600, 0, 0, False), (0x1600, 1, 0x60400010, True), (0x1600, 0, 1, True)],
            id="mapping-without-comm",
        ),
        pytest.param(
            {(0x1400, 2): 1, (0x1400, 1): 0x80000201},
            [(0x1400, 1, 0x80000201, False), (0x1400, 2, 1, True), (0x1400, 1, 0x80000201, True)],
            id="invalid-pdo-stays-invalid",
        ),
        pytest.param(
            {(0x1801, 2): 1, (0x1A01, 1): 0x60640020},
            [(0x1A01, 1, 0x60640020, True), (0x1801, 2, 1, True)],
            id="no-cob-id-no-count",
        ),
        pytest.param(
            {(0x1005, 0): 0x40000080, (0x1007, 0): 0, (0x1006, 0): 1000},
            [(0x1006, 0, 1000, True), (0x1007, 0, 0, True), (0x1005, 0, 0x40000080, True)],
            id="sync-cob-id-after-period",
        ),
    ],
)
def test_pdo_and_sync_order(values: dict[tuple[int, int], Value], expected: list[Step]) -> None:
    assert steps(values) == expected


def test_areas_in_order_and_receive_pdos_before_transmit_pdos() -> None:
    values: dict[tuple[int, int], Value] = {
        (0xA000, 0): 1,
        (0x6065, 0): 500,  # Following error window
        (0x2006, 8): 3000,  # PA-103
        (0x1A00, 0): 0,
        (0x1600, 0): 0,
        (0x1017, 0): 100,  # Producer heartbeat time
        (0x1016, 1): 0x00050064,  # Consumer heartbeat time
        (0x5FF1, 0): -5,
    }
    order = [(index, sub) for index, sub, _, final in steps(values) if final]
    assert order == [
        (0x1016, 1),
        (0x1017, 0),
        (0x1600, 0),
        (0x1A00, 0),
        (0x2006, 8),
        (0x5FF1, 0),
        (0x6065, 0),
        (0xA000, 0),
    ]


def test_every_value_is_written_once_as_final() -> None:
    values = {**TPDO1, (0x6065, 0): 1, (0x1017, 0): 0}
    finals = [(w.index, w.subindex) for w in plan_writes(values) if w.final]
    assert sorted(finals) == sorted(values)
    assert all(isinstance(w, Write) for w in plan_writes(values))


def sub(index: int, access: Access, *, flags: int = 0) -> OdSub:
    return OdSub(index, 1, "x", DataType.UNSIGNED32, access, False, obj_flags=flags)


@pytest.mark.parametrize(
    ("entry", "reason"),
    [
        (sub(0x6065, "rw"), None),
        (sub(0x2006, "wo"), None),
        (sub(0x1800, "rww"), None),
        (sub(0x6041, "ro"), "read-only"),
        (sub(0x1000, "const"), "read-only"),
        (sub(0x1010, "rw"), "a command, not a setting"),  # Store parameters
        (sub(0x1011, "rw"), "a command, not a setting"),  # Restore default parameters
        (sub(0x1003, "rw"), "a command, not a setting"),  # Pre-defined error field
        (sub(0x6040, "rw"), "a command, not a setting"),  # Controlword
        (sub(0x2000, "rw", flags=0x1), "the file marks it not to be written on download"),
    ],
)
def test_skip_reason(entry: OdSub, reason: str | None) -> None:
    found = skip_reason(entry)
    assert found == reason or (
        reason is not None and found is not None and found.startswith(reason)
    )
