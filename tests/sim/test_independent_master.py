"""An independent master drives every simulated profile: python-canopen's BaseNode402 over a
virtual bus, against drives running in a SimBus thread — no ServoDesk code on the master side."""

from __future__ import annotations

import time
import uuid
from collections.abc import Callable, Iterator

import can
import canopen
import pytest
from canopen.profiles.p402 import BaseNode402

from servodesk_data import PROFILE_NAMES, eds_path
from servodesk_sim.runner import SimBus, run_drives

NODE = 5


@pytest.fixture(params=PROFILE_NAMES)
def node(request: pytest.FixtureRequest) -> Iterator[BaseNode402]:
    profile: str = request.param
    channel = f"master402-{uuid.uuid4().hex}"
    drive_bus = can.Bus(interface="virtual", channel=channel)
    sim: SimBus = run_drives(drive_bus, [(NODE, profile)])
    network = canopen.Network()
    network.connect(interface="virtual", channel=channel)
    try:
        master = BaseNode402(NODE, str(eds_path(profile)))  # type: ignore[no-untyped-call]
        network.add_node(master)
        master.sdo.RESPONSE_TIMEOUT = 1.0
        master.nmt.state = "PRE-OPERATIONAL"
        configure_status_tpdo(master)
        master.setup_402_state_machine()  # type: ignore[no-untyped-call]
        master.nmt.state = "OPERATIONAL"
        # Entering Operational makes event-driven TPDOs report the statusword once.
        assert wait_until(lambda: master.statusword != 0, timeout=2.0)
        yield master
    finally:
        network.disconnect()
        sim.stop()
        drive_bus.shutdown()


def configure_status_tpdo(master: BaseNode402) -> None:
    """Map statusword + mode display into TPDO1, event-driven with a 20 ms event timer, in the
    order every profile accepts (MDi-S1-C manual §2.5: invalidate, clear, map, count, validate).
    python-canopen's BaseNode402 treats a TPDO it has seen twice in a row as periodic and then
    waits for the next one, so a master needs the event timer with event-driven TPDOs."""
    cob_id = 0x180 + NODE
    master.sdo[0x1800][1].raw = 0xC0000000 | cob_id  # TPDO1 COB-ID: invalid
    master.sdo[0x1A00][0].raw = 0
    master.sdo[0x1A00][1].raw = 0x60410010  # Statusword
    master.sdo[0x1A00][2].raw = 0x60610008  # Modes of operation display
    master.sdo[0x1A00][0].raw = 2
    master.sdo[0x1800][2].raw = 255  # event-driven
    master.sdo[0x1800][5].raw = 20  # event timer, ms
    master.sdo[0x1800][1].raw = 0x40000000 | cob_id  # valid


def wait_until(condition: Callable[[], bool], timeout: float = 5.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.01)
    return condition()


def test_state_machine_reaches_operation_enabled_and_back(node: BaseNode402) -> None:
    assert node.state == "SWITCH ON DISABLED"
    node.state = "OPERATION ENABLED"
    assert node.state == "OPERATION ENABLED"
    assert node.sdo[0x6041].raw & 0x6F == 0x27  # Statusword: operation enabled
    node.state = "SWITCH ON DISABLED"
    assert node.sdo[0x6041].raw & 0x4F == 0x40


def test_profile_velocity_moves_the_axis(node: BaseNode402) -> None:
    node.op_mode = "PROFILED VELOCITY"
    assert node.sdo[0x6061].raw == 3  # Modes of operation display
    node.state = "OPERATION ENABLED"
    node.sdo[0x60FF].raw = 200_000  # Target velocity: 2 rev/s in user units/s
    start = node.sdo[0x6064].raw
    assert wait_until(lambda: abs(node.sdo[0x606C].raw - 120) <= 2)  # 2 rev/s = 120 rpm
    assert node.sdo[0x6041].raw & 0x0400  # target velocity reached
    assert wait_until(lambda: node.sdo[0x6064].raw > start)  # Position actual value moves


def test_profile_position_reaches_the_target(node: BaseNode402) -> None:
    node.op_mode = "PROFILED POSITION"
    assert node.sdo[0x6061].raw == 1
    node.state = "OPERATION ENABLED"
    node.sdo[0x6081].raw = 200_000  # Profile velocity
    node.sdo[0x607A].raw = 50_000  # Target position: half a revolution
    node.controlword = 0x1F  # new set-point
    assert wait_until(lambda: node.sdo[0x6041].raw & 0x1000 != 0)  # set-point acknowledge
    node.controlword = 0x0F
    assert wait_until(lambda: node.sdo[0x6041].raw & 0x0400 != 0)  # target reached
    assert node.sdo[0x6064].raw == pytest.approx(50_000, abs=100)


def test_homing_method_35_sets_the_home_offset(node: BaseNode402) -> None:
    node.sdo[0x607C].raw = 1234  # Home offset
    node.sdo[0x6098].raw = 35  # Homing method: current position
    assert node.homing(timeout=5)  # type: ignore[no-untyped-call]
    assert node.sdo[0x6061].raw == 6
    assert node.sdo[0x6064].raw == 1234
    assert node.sdo[0x6041].raw & 0x1400 == 0x1400  # homing attained, target reached
