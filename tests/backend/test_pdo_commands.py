"""Which RPDO a command can travel in, and its frame (pure)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from servodesk.pdo.commands import ip_route_in, route_in
from servodesk.pdo.model import MappedObject, PdoConfig


def rpdo(number: int, objects: list[tuple[int, int, int]], *, kind: int = 255) -> PdoConfig:
    return PdoConfig(
        kind="rpdo",
        number=number,
        cob_id=0x100 + number * 0x100 + 3,
        valid=True,
        transmission_type=kind,
        mapping=tuple(MappedObject(i, s, b) for i, s, b in objects),
    )


PV = rpdo(1, [(0x6040, 0, 16), (0x60FF, 0, 32), (0x6060, 0, 8)])


@pytest.mark.parametrize(
    ("values", "frame"),
    [
        # controlword 010Fh (halt), 60FFh 166 667, 6060h 3
        ({0x6040: 0x010F, 0x60FF: 166_667, 0x6060: 3}, "0f010b8b020003"),
        # a negative set-point goes as its two's complement, 6060h as a signed byte
        ({0x6040: 0x000F, 0x60FF: -1, 0x6060: -1}, "0f00ffffffffff"),
        # 6060h unknown: no frame (the command takes SDO)
        ({0x6040: 0x000F, 0x60FF: 5}, None),
    ],
)
def test_frame_of_known_values(values: dict[int, int], frame: str | None) -> None:
    route = route_in([PV], 0x60FF)
    assert route is not None
    assert route.label == "RPDO1"
    assert route.cob_id == 0x203
    data = route.payload(values)
    assert (data.hex() if data is not None else None) == frame


@pytest.mark.parametrize(
    ("pdos", "index", "label"),
    [
        ([PV], 0x6040, "RPDO1"),
        ([PV], 0x6060, None),  # a mode is written by SDO: an unsupported one is refused there
        ([rpdo(1, [(0x6040, 0, 16), (0x60FF, 0, 32)], kind=1)], 0x60FF, None),  # on SYNC
        ([rpdo(1, [(0x6083, 0, 32)]), rpdo(2, [(0x6071, 0, 16)])], 0x6071, "RPDO2"),
        ([rpdo(1, [(0x60C1, 1, 32), (0x6040, 0, 16)])], 0x6040, None),  # a record's sub
        ([rpdo(1, [(0x0006, 0, 8), (0x607A, 0, 32)])], 0x607A, "RPDO1"),  # dummy: zeros
    ],
)
def test_route_choice(pdos: list[PdoConfig], index: int, label: str | None) -> None:
    route = route_in(pdos, index)
    assert (route.label if route else None) == label


def test_a_dummy_sends_zeros() -> None:
    route = route_in([rpdo(1, [(0x0006, 0, 8), (0x607A, 0, 32)])], 0x607A)
    assert route is not None
    assert route.payload({0x607A: 0x01020304}) == bytes.fromhex("0004030201")


def test_an_invalid_rpdo_is_not_used() -> None:
    assert route_in([replace(PV, valid=False)], 0x60FF) is None


@pytest.mark.parametrize(
    ("pdos", "found"),
    [
        # the manuals' IP mapping, taken at SYNC
        ([rpdo(1, [(0x6040, 0, 16), (0x60C1, 1, 32), (0x6060, 0, 8)], kind=1)], ("RPDO1", True)),
        # on receipt works too (the drive then holds it until its next SYNC)
        ([rpdo(2, [(0x60C1, 1, 32)])], ("RPDO2", False)),
        # another object beside it: its value is not the stream's to send
        ([rpdo(1, [(0x60C1, 1, 32), (0x6083, 0, 32)], kind=1)], None),
        # no 60C1h:01
        ([PV], None),
        # acyclic (type 0): not one per SYNC
        ([rpdo(1, [(0x6040, 0, 16), (0x60C1, 1, 32)], kind=0)], None),
    ],
)
def test_ip_route_choice(pdos: list[PdoConfig], found: tuple[str, bool] | None) -> None:
    route = ip_route_in(pdos)
    assert ((route[0].label, route[1]) if route else None) == found


def test_ip_frame() -> None:
    route = ip_route_in([rpdo(1, [(0x6040, 0, 16), (0x60C1, 1, 32), (0x6060, 0, 8)], kind=1)])
    assert route is not None
    frame = route[0].payload({0x6040: 0x001F, 0x60C1: -2, 0x6060: 7})
    assert frame == bytes.fromhex("1f00feffffff07")
