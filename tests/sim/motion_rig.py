"""A MotionCore on DictValues, wired the way the drive composition wires it, for the motion tests.

Faults the core reports are answered with enter_fault() after the call returns, as the drive
does; fault reset succeeds unless `faults_persist` is set.
"""

from __future__ import annotations

from dataclasses import replace

from servodesk_data import LimitSwitchReaction
from servodesk_data.fault_kind import FaultKind
from servodesk_protocol.cia402 import Cia402State
from servodesk_sim.motion import MotionConfig, MotionCore
from servodesk_sim.values import DictValues

DT = 0.001
REV = 100000  # user units per revolution with the default gear ratio
INC = 131072  # encoder increments per revolution

MDI_CONFIG = MotionConfig(
    supported_modes=frozenset({1, 3, 4, 6, 7}),
    homing_methods=frozenset({17, 18, 23, 27, 35}),
    immediate_setpoint=False,
    unsupported_mode_display=0,
    reference_found_bit15=False,
    max_speed=(0x2006, 8, "rpm"),
    limit_switch_reaction=LimitSwitchReaction.INHIBIT,
)
CIA402_CONFIG = replace(
    MDI_CONFIG,
    immediate_setpoint=True,
    unsupported_mode_display=None,
    max_speed=(0x6080, 0, "rpm"),
    limit_switch_reaction=LimitSwitchReaction.FAULT,
)
KINCO_CONFIG = replace(CIA402_CONFIG, reference_found_bit15=True)

# MDi factory values (MDi-S1-C manual §5.3) plus the simulator's switch layout.
MDI_VALUES: dict[tuple[int, int], int] = {
    (0x6040, 0): 0,  # Controlword
    (0x605A, 0): 1,  # Quick stop option code
    (0x6060, 0): 0,  # Modes of operation
    (0x6065, 0): 100000,  # Following error window
    (0x6067, 0): 100,  # Position window
    (0x6071, 0): 0,  # Target torque
    (0x6072, 0): 3000,  # Max torque
    (0x607A, 0): 0,  # Target position
    (0x607C, 0): 0,  # Home offset
    (0x607E, 0): 0,  # Polarity
    (0x6081, 0): 100000,  # Profile velocity
    (0x6083, 0): 100000,  # Profile acceleration
    (0x6084, 0): 100000,  # Profile deceleration
    (0x6085, 0): 100000,  # Quick stop deceleration
    (0x6087, 0): 1,  # Torque slope
    (0x6091, 1): INC,  # Gear ratio: motor increments
    (0x6091, 2): REV,  # Gear ratio: user units
    (0x6098, 0): 17,  # Homing method
    (0x6099, 1): 100000,  # Homing speed: search for switch
    (0x6099, 2): 20000,  # Homing speed: search for zero
    (0x609A, 0): 1000000,  # Homing acceleration
    (0x60C1, 1): 0,  # Interpolation data record
    (0x60C2, 1): 1,  # Interpolation time period value
    (0x60C2, 2): -3,  # Interpolation time index
    (0x60FF, 0): 0,  # Target velocity
    (0x2006, 8): 6000,  # PA-103 maximum speed (rpm)
    (0x5FF1, 0): -5 * INC,  # SIM N-OT position
    (0x5FF2, 0): 5 * INC,  # SIM P-OT position
    (0x5FF3, 0): INC,  # SIM home switch start
    (0x5FF4, 0): INC + INC // 4,  # SIM home switch end
}


class Rig:
    def __init__(
        self,
        config: MotionConfig = MDI_CONFIG,
        overrides: dict[tuple[int, int], int] | None = None,
    ) -> None:
        self.values = DictValues({**MDI_VALUES, **(overrides or {})})
        self.faults: list[FaultKind] = []
        self.resets = 0
        self.faults_persist = False
        self.core = MotionCore(self.values, config, self._on_fault, self._fault_reset)
        self._new_faults = 0

    def _on_fault(self, kind: FaultKind) -> None:
        self.faults.append(kind)
        self._new_faults += 1

    def _fault_reset(self) -> bool:
        self.resets += 1
        return not self.faults_persist

    def _settle(self) -> None:
        while self._new_faults:
            self._new_faults -= 1
            self.core.enter_fault()

    def __getitem__(self, key: int | tuple[int, int]) -> int:
        index, sub = key if isinstance(key, tuple) else (key, 0)
        return self.values.get(index, sub)

    def __setitem__(self, key: int | tuple[int, int], value: int) -> None:
        index, sub = key if isinstance(key, tuple) else (key, 0)
        self.values.set(index, sub, value)

    @property
    def statusword(self) -> int:
        return self.values.get(0x6041)

    @property
    def state(self) -> Cia402State:
        return self.core.state

    def controlword(self, value: int) -> None:
        """Write 6040h as an SDO or RPDO would: the value first, then the core."""
        self.values.set(0x6040, 0, value)
        self.core.on_controlword(value)
        self._settle()

    def step(self, count: int = 1) -> None:
        for _ in range(count):
            self.core.step(DT)
            self._settle()

    def run(self, seconds: float) -> None:
        self.step(round(seconds / DT))

    def run_until(self, mask: int, value: int, limit: float = 3.0) -> float:
        """Step until statusword & mask == value; returns the simulated time it took."""
        for n in range(round(limit / DT)):
            if self.statusword & mask == value:
                return n * DT
            self.step()
        raise AssertionError(f"statusword {self.statusword:#06x} never matched within {limit} s")

    def enable(self, mode: int | None = None) -> None:
        """Shutdown, switch on, enable operation (the path BaseNode402 takes)."""
        if mode is not None:
            self[0x6060] = mode
        for word in (0x06, 0x07, 0x0F):
            self.controlword(word)
        self.step()
