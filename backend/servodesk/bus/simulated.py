"""The built-in simulated drives: three drives on a private python-can virtual channel.

This is the only place in the backend that imports the simulator (the import contract in
pyproject.toml checks it), and BusManager imports this module only when it starts simulated
drives, so a bus on a real adapter never loads the simulator. The tool connects to the channel
with its own bus instance, exactly as it would to a real adapter.
"""

from __future__ import annotations

import uuid
from dataclasses import dataclass

import can

from servodesk_sim.runner import SimBus, build_drives

__all__ = ["SIM_DRIVES", "SIM_INTERFACE", "SimBus", "SimulatedDrives", "prepare_simulated_drives"]
# SimBus is exported for BusManager.sim's type: the simulator is named here and nowhere else

SIM_INTERFACE = "virtual"
# node id, profile: one drive of each family the tool ships profiles for
SIM_DRIVES: tuple[tuple[int, str], ...] = ((1, "mdi-s1c"), (2, "kinco"), (3, "cia402"))


@dataclass
class SimulatedDrives:
    channel: str
    sim: SimBus
    bus: can.BusABC  # the drives' own bus instance
    interface: str = SIM_INTERFACE  # what the tool opens to join `channel`

    def start(self) -> None:
        """Power the drives on (blocking: they send their boot-up frames before this returns)."""
        self.sim.start()

    def stop(self) -> None:
        """Stop the drives and close their bus (blocking: joins the drive thread)."""
        try:
            self.sim.stop()
        finally:
            self.bus.shutdown()


def prepare_simulated_drives(
    drives: tuple[tuple[int, str], ...] = SIM_DRIVES,
) -> SimulatedDrives:
    """The drives on a fresh private channel, still powered off: the tool joins the channel
    first and then calls `start()`, so it sees their boot-ups as it would on a real bus."""
    channel = f"servodesk-sim-{uuid.uuid4().hex[:12]}"
    # the drives stamp their frames with their time on the simulated wire (servodesk_sim.runner)
    bus = can.Bus(interface=SIM_INTERFACE, channel=channel, preserve_timestamps=True)
    try:
        sim = build_drives(bus, drives)
    except BaseException:
        bus.shutdown()
        raise
    return SimulatedDrives(channel=channel, sim=sim, bus=bus)
