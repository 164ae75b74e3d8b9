"""A recording of a bus whose name ends in a long number (the simulated bus's random name can):
python-can reads that number as the channel, which a BLF or MF4 file cannot hold; every frame
is still written, as the file's default channel."""

from __future__ import annotations

from pathlib import Path

import can
import pytest

from servodesk.logs.recording import RecordingFormat, _Recording


@pytest.mark.parametrize("fmt", [RecordingFormat.BLF, RecordingFormat.MF4, RecordingFormat.ASC])
def test_a_channel_name_ending_in_a_long_number_is_recorded(
    tmp_path: Path, fmt: RecordingFormat
) -> None:
    path = tmp_path / f"rec.{fmt.value}"
    recording = _Recording(path, fmt)
    for n in range(5):
        recording.tap.on_message_received(
            can.Message(
                arbitration_id=0x581,
                data=bytes([0x43, 0, 0x10, 0, n, 0, 0, 0]),
                is_extended_id=False,
                channel="servodesk-sim-4817290",
                timestamp=1_700_000_000.0 + n / 1000,
            )
        )
    recording.finish()
    frames = [m for m in can.LogReader(path) if m.arbitration_id == 0x581]
    assert [m.data[4] for m in frames] == [0, 1, 2, 3, 4]
    assert recording.tap.dropped == 0
