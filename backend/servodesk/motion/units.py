"""Drive units ↔ engineering units, both ways (pure).

What the simulated drives use (docs/simulator.md "Units", the literal reading of MDi-S1-C
CANopen manual §3.1 and §5.3; Kinco and the CiA 402 controller follow the same plant):

- positions 607Ah, 607Ch, 6064h, 60C1h:01, 60F4h, 6065h, 6067h: user units; the gear ratio
  6091h maps 6091h:01 motor increments to 6091h:02 user units (default 131072 : 100000);
- 6063h: encoder increments (131072 per revolution on the 17-bit encoder);
- velocities 6081h, 60FFh, 6099h:01/02: user units/s;
- accelerations 6083h, 6084h, 6085h, 609Ah: user units/s per ms ("Inc/s/ms" read literally);
- 606Ch, the overspeed object (MDi PA-103 2006h:08, else 6080h): motor rpm;
- torques 6071h, 6072h, 6077h: 0.1 % of rated torque; slope 6087h: 0.1 %/ms.

`DriveUnits.velocity_actual_rpm` says whether 606Ch is rpm (the three profiles) or, as CiA 402
leaves it to the device, the velocity unit of 60FFh (the fallback for unknown drives).
Positions are on the motor side in increments (`_inc`) and revolutions (`_rev`).
"""

from __future__ import annotations

from dataclasses import dataclass

ENCODER_COUNTS = 131072  # 17-bit encoder, increments per revolution (MDi-S1-C manual §3.1)
DEFAULT_USER_UNITS = 100000  # 6091h:02 factory value: 100000 user units per 131072 increments
TORQUE_PER_PCT = 10  # 6071h/6077h are 0.1 % of rated torque
MS_PER_S = 1000
S_PER_MIN = 60.0


@dataclass(frozen=True, slots=True)
class DriveUnits:
    counts_per_rev: int = ENCODER_COUNTS  # 608Fh where the drive has it
    motor_increments: int = ENCODER_COUNTS  # 6091h:01
    user_units: int = DEFAULT_USER_UNITS  # 6091h:02
    velocity_actual_rpm: bool = True  # 606Ch in rpm (else in 60FFh's units)

    @classmethod
    def of(
        cls,
        counts_per_rev: int | None,
        gear: tuple[int, int] | None,
        *,
        velocity_actual_rpm: bool = True,
    ) -> DriveUnits:
        """Units from what the drive reports; a zero or missing half keeps the default (the
        simulated drives do the same)."""
        counts = counts_per_rev if counts_per_rev and counts_per_rev > 0 else ENCODER_COUNTS
        motor, user = gear if gear and gear[0] > 0 and gear[1] > 0 else (counts, DEFAULT_USER_UNITS)
        return cls(counts, motor, user, velocity_actual_rpm)

    @property
    def gear(self) -> tuple[int, int]:
        return self.motor_increments, self.user_units

    @property
    def user_per_rev(self) -> float:
        return self.user_units * self.counts_per_rev / self.motor_increments

    # positions
    def user_to_inc(self, user: float) -> int:
        return round(user * self.motor_increments / self.user_units)

    def inc_to_user(self, inc: float) -> int:
        return round(inc * self.user_units / self.motor_increments)

    def inc_to_rev(self, inc: float) -> float:
        return inc / self.counts_per_rev

    def rev_to_inc(self, rev: float) -> int:
        return round(rev * self.counts_per_rev)

    def rev_to_user(self, rev: float) -> int:
        return round(rev * self.user_per_rev)

    def user_to_rev(self, user: float) -> float:
        return user / self.user_per_rev

    # velocities
    def rpm_to_velocity(self, rpm: float) -> int:
        """Motor rpm to 60FFh / 6081h / 6099h user units/s."""
        return round(rpm / S_PER_MIN * self.user_per_rev)

    def velocity_to_rpm(self, velocity: float) -> float:
        return velocity / self.user_per_rev * S_PER_MIN

    def actual_velocity_rpm(self, raw: int) -> float:
        """606Ch Velocity actual value in rpm."""
        return float(raw) if self.velocity_actual_rpm else self.velocity_to_rpm(raw)

    # accelerations
    def rpm_s_to_acceleration(self, rpm_s: float) -> int:
        """rpm/s to 6083h/6084h/609Ah user units/s per ms; at least 1 (0 counts as 1 anyway)."""
        return max(1, round(rpm_s / S_PER_MIN * self.user_per_rev / MS_PER_S))

    def acceleration_to_rpm_s(self, raw: float) -> float:
        return raw * MS_PER_S / self.user_per_rev * S_PER_MIN

    # torques
    @staticmethod
    def pct_to_torque(pct: float) -> int:
        """% rated torque to 6071h / 6072h (0.1 %)."""
        return round(pct * TORQUE_PER_PCT)

    @staticmethod
    def torque_to_pct(raw: float) -> float:
        return raw / TORQUE_PER_PCT

    @staticmethod
    def pct_per_s_to_slope(pct_per_s: float) -> int:
        """% rated torque per second to 6087h Torque slope (0.1 %/ms); at least 1."""
        return max(1, round(pct_per_s * TORQUE_PER_PCT / MS_PER_S))
