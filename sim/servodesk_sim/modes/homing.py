"""Homing mode (6060h = 6), methods 17, 18, 23, 27 and 35 as MDi-S1-C manual §3.7.3 describes them.

Every search method is the same shape: from outside its switch it runs fast (6099h:01) in its
first direction until the switch's rising edge, then brakes, reverses and runs slow (6099h:02)
until the falling edge; from inside the switch it runs slow the other way to the falling edge
at once. 17/18 use N-OT/P-OT as home switch, 23/27 the home switch HW and reverse at the limit
switch in their first direction ("遇到限位开关，自动反向"), then look for HW fast and slow in the
same direction. 35 takes the current position. Ramps use 609Ah.

On completion the axis stops and its position becomes the home offset 607Ch ("原点回零成后，电机
停止位置为机械原点", MDi-S1-C manual §3.7). Switches and directions are those of the motor frame, so
the
physical switches stay put under 607Eh polarity. A limit switch other than the method's own, or
no home within the homing timeout, is a homing error. Controlword bit 4 0 -> 1 starts homing;
1 -> 0 only acknowledges it ("1-->0: 驱动接收到回零信号"). Halt (bit 8) interrupts it.
Statusword bits 13/12/10 follow CiA 402 (MDi-S1-C manual's "回零" wording for bit 12 is read as
"homing attained"): in progress 0/0/0, interrupted or not started 0/0/1, attained while still
moving 0/1/0, done 0/1/1, error 1/0/0 moving or 1/0/1 at standstill.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from servodesk_protocol.cia402 import (
    CW_HALT,
    CW_NEW_SETPOINT,
    SW_MODE_BIT12,
    SW_MODE_BIT13,
    SW_TARGET_REACHED,
)
from servodesk_sim.fault_kind import FaultKind
from servodesk_sim.modes.common import (
    Axis,
    Setpoint,
    Switches,
    acceleration,
    ramp_velocity,
)
from servodesk_sim.plant import ControlKind, read_or
from servodesk_sim.values import ValueStore

CURRENT_POSITION_METHODS = frozenset({35, 37})  # 37 is CiA 402's newer number for 35
SETTLE_LIMIT = 0.5  # s after the stop at most, to let the axis come to the demand


class Phase(Enum):
    IDLE = "idle"  # never started since power-up
    SEARCHING = "searching"
    STOPPING = "stopping"  # home edge found, braking
    DONE = "done"
    INTERRUPTED = "interrupted"
    ERROR = "error"


@dataclass(frozen=True, slots=True)
class Leg:
    """Run in `direction` (motor frame) until `switch` shows the given edge."""

    direction: int  # +1 or -1
    fast: bool
    switch: Switches
    rising: bool
    home: bool = False  # this edge is the home position: stop after it


@dataclass(frozen=True, slots=True)
class Method:
    switch: Switches  # the home switch
    direction: int  # first search direction from outside the switch
    reverses_at_limit: bool  # 23/27

    def outside(self) -> tuple[Leg, ...]:
        d = self.direction
        return (Leg(d, True, self.switch, True), Leg(-d, False, self.switch, False, home=True))

    def inside(self) -> tuple[Leg, ...]:
        return (Leg(-self.direction, False, self.switch, False, home=True),)

    def after_limit(self) -> tuple[Leg, ...]:
        d = -self.direction
        return (Leg(d, True, self.switch, True), Leg(d, False, self.switch, False, home=True))


METHODS: dict[int, Method] = {
    17: Method(Switches.NEGATIVE_LIMIT, -1, reverses_at_limit=False),
    18: Method(Switches.POSITIVE_LIMIT, +1, reverses_at_limit=False),
    23: Method(Switches.HOME, +1, reverses_at_limit=True),
    27: Method(Switches.HOME, -1, reverses_at_limit=True),
}


def _limit(direction: int) -> Switches:
    return Switches.POSITIVE_LIMIT if direction > 0 else Switches.NEGATIVE_LIMIT


class Homing:
    def __init__(self, methods: frozenset[int], timeout: float) -> None:
        self._methods = methods
        self._timeout = timeout
        self.phase = Phase.IDLE
        self._method: Method | None = None
        self._legs: tuple[Leg, ...] = ()
        self._leg = 0
        self._reversed_at_limit = False
        self._begin = False  # started by controlword, legs chosen at the next step
        self._halted = False
        self._position = 0.0
        self._velocity = 0.0
        self._elapsed = 0.0
        self._switches = Switches(0)
        self._fault_due = False
        self._settling = 0.0

    @property
    def referenced(self) -> bool:
        """The last homing run succeeded (Kinco "reference found")."""
        return self.phase is Phase.DONE

    def start(self, values: ValueStore, axis: Axis) -> None:
        """Enter the mode: stand still; a run cut short by leaving the mode is interrupted."""
        self._position = axis.position
        self._velocity = 0.0
        self._begin = False
        if self.phase in (Phase.SEARCHING, Phase.STOPPING):
            self.phase = Phase.INTERRUPTED

    def on_controlword(self, values: ValueStore, controlword: int, previous: int) -> None:
        self._halted = bool(controlword & CW_HALT)
        edge = controlword & CW_NEW_SETPOINT and not previous & CW_NEW_SETPOINT
        if edge and not self._halted and self.phase not in (Phase.SEARCHING, Phase.STOPPING):
            # Shown at once, so a statusword read right after the write says "in progress".
            self.phase = Phase.SEARCHING
            self._begin = True
            self._elapsed = 0.0
        elif self._halted and self.phase in (Phase.SEARCHING, Phase.STOPPING):
            self.phase = Phase.INTERRUPTED

    def step(self, dt: float, values: ValueStore, axis: Axis) -> Setpoint:
        previous, self._switches = self._switches, axis.switches
        if self._begin:
            self._begin = False
            self._plan(values, axis)
            previous = axis.switches  # no edge on the first period
        target = 0.0
        if self.phase is Phase.SEARCHING:
            self._elapsed += dt
            self._search(previous, axis)
            if self.phase is Phase.SEARCHING and self._elapsed > self._timeout:
                self._fail()  # no home within the travel the timeout allows
        if self.phase is Phase.SEARCHING:
            leg = self._legs[self._leg]
            fast = 1 if leg.fast else 2  # 6099h:01 search for switch, :02 search for zero
            speed = float(read_or(values, 0x6099, fast, 100000 if leg.fast else 20000))
            target = leg.direction * speed * (-1.0 if axis.scaling.reversed else 1.0)
        acc = acceleration(read_or(values, 0x609A, 0, 1000000))  # Homing acceleration
        new_velocity = ramp_velocity(self._velocity, target, acc, acc, dt)
        self._position += 0.5 * (self._velocity + new_velocity) * dt
        self._velocity = new_velocity
        shift = None
        if self.phase is Phase.STOPPING and new_velocity == 0.0:
            self._settling += dt
            # Wait for the axis to stand at the demand so the position read afterwards is
            # exactly 607Ch; a position loop that cannot settle still finishes.
            if abs(axis.position - self._position) < 0.5 or self._settling > SETTLE_LIMIT:
                offset = float(read_or(values, 0x607C, 0, 0))  # Home offset
                shift, self._position = offset - self._position, offset
                self.phase = Phase.DONE
        fault = None
        if self._fault_due:
            self._fault_due = False
            fault = FaultKind.HOMING_ERROR
        return Setpoint(
            ControlKind.POSITION,
            position=self._position,
            velocity=self._velocity,
            position_shift=shift,
            fault=fault,
        )

    def _plan(self, values: ValueStore, axis: Axis) -> None:
        number = read_or(values, 0x6098, 0, 17)  # Homing method
        self._reversed_at_limit = False
        self._leg = 0
        self._settling = 0.0
        if number not in self._methods:
            self._fail()
        elif number in CURRENT_POSITION_METHODS:
            self.phase = Phase.STOPPING  # nothing to search: take the position as it stands
        elif (method := METHODS.get(number)) is None:
            self._fail()
        else:
            self._method = method
            self._legs = method.inside() if axis.switches & method.switch else method.outside()

    def _fail(self) -> None:
        self.phase = Phase.ERROR
        self._fault_due = True

    def _search(self, previous: Switches, axis: Axis) -> None:
        method = self._method
        if method is None:
            return
        leg = self._legs[self._leg]
        limit = _limit(leg.direction)
        if axis.switches & limit and limit != method.switch:
            first_leg = self._leg == 0 and leg.direction == method.direction
            if method.reverses_at_limit and first_leg and not self._reversed_at_limit:
                self._reversed_at_limit = True
                self._legs, self._leg = method.after_limit(), 0
            else:
                self._fail()
            return
        moving = axis.motor_velocity * leg.direction > 0.0
        was, now = bool(previous & leg.switch), bool(axis.switches & leg.switch)
        if moving and now != was and now == leg.rising:
            if leg.home:
                self.phase = Phase.STOPPING
            else:
                self._leg += 1

    def take_over(self, position: float) -> None:
        """Never called: homing runs into the limit switches on purpose, nothing holds it."""

    def status_bits(self, axis: Axis) -> int:
        standstill = self._velocity == 0.0
        if self.phase is Phase.DONE:
            return SW_MODE_BIT12 | (SW_TARGET_REACHED if standstill else 0)
        if self.phase is Phase.ERROR:
            return SW_MODE_BIT13 | (SW_TARGET_REACHED if standstill else 0)
        if self.phase in (Phase.IDLE, Phase.INTERRUPTED):
            return SW_TARGET_REACHED if standstill else 0
        return 0
