"""The scope's tap on the bus: frames of the wanted COB-IDs into a queue, nothing else.

python-can calls `on_message_received` on its notifier thread for every frame on the bus, so it
only filters by id and appends (arrival time, payload) — no decoding, no I/O (DESIGN rule 1).
The flush task drains the queue in batches and decodes them with numpy (batch.py).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable

import can

Frame = tuple[int, float, bytes]  # (CAN id, arrival time in epoch s, payload)
DEFAULT_LIMIT = 2_000_000  # frames waiting for the flush: minutes of a saturated bus


class FrameSink(can.Listener):
    def __init__(self, cob_ids: Iterable[int], *, limit: int = DEFAULT_LIMIT) -> None:
        self._wanted = frozenset(cob_ids)
        # deque.append / popleft are atomic: the notifier appends while the flush drains
        self._frames: deque[Frame] = deque()
        self._limit = limit
        self.lost = 0  # frames dropped because the flush fell `limit` frames behind
        self.received = 0

    @property
    def cob_ids(self) -> frozenset[int]:
        return self._wanted

    def on_message_received(self, msg: can.Message) -> None:
        can_id = msg.arbitration_id
        if can_id not in self._wanted or msg.is_remote_frame or msg.is_extended_id:
            return
        if len(self._frames) >= self._limit:
            self.lost += 1
            return
        self.received += 1
        self._frames.append((can_id, msg.timestamp, bytes(msg.data)))

    def drain(self) -> list[Frame]:
        """Everything queued so far, oldest first (frames arriving meanwhile stay queued)."""
        frames = self._frames
        count = len(frames)
        popleft = frames.popleft
        return [popleft() for _ in range(count)]

    def push(self, frame: Frame) -> None:
        """A sample that did not come off the bus (SDO polling), in the same queue."""
        self._frames.append(frame)
