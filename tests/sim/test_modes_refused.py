"""6060h Modes of operation over SDO: a mode the drive does not support is refused with abort
06090030 (value range exceeded) on the drives that keep their mode (Kinco, CiA 402); each
supported mode is taken and shown in 6061h. The MDi shows an unsupported in-range mode as
6061h = 0 (MDi-S1-C CANopen manual §3.3) and refuses values beyond its range (06090031/32)."""

from __future__ import annotations

import pytest

from tests.sim.drive_rig import DriveRig


@pytest.mark.parametrize("profile", ["kinco", "cia402"])
@pytest.mark.parametrize(("mode", "byte"), [(9, "09"), (100, "64"), (-100, "9C"), (2, "02")])
def test_unsupported_modes_abort_06090030(profile: str, mode: int, byte: str) -> None:
    rig = DriveRig(1, profile)
    before = rig.read(0x6061)
    # expedited download of one byte to 6060h:00 → abort 06090030, exact frame
    assert rig.sdo(f"2F 60 60 00 {byte} 00 00 00") == "80 60 60 00 30 00 09 06"
    rig.advance(0.01)
    assert rig.read(0x6061) == before


@pytest.mark.parametrize("profile", ["kinco", "cia402", "mdi-s1c"])
def test_supported_modes_are_taken_and_shown(profile: str) -> None:
    rig = DriveRig(1, profile)
    for mode in sorted(rig.drive.data.quirks.supported_modes):
        rig.write_ok(0x6060, 0, mode, 1)
        rig.advance(0.01)
        assert rig.read(0x6061) == mode


def test_the_mdi_refuses_modes_beyond_its_range() -> None:
    rig = DriveRig(1, "mdi-s1c")
    # its EDS range 0–7: 06090031 value too high / 06090032 too low (the range family)
    assert rig.sdo("2F 60 60 00 09 00 00 00") == "80 60 60 00 31 00 09 06"
    assert rig.sdo("2F 60 60 00 9C 00 00 00") == "80 60 60 00 32 00 09 06"
