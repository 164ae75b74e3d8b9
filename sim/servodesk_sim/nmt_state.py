"""NMT states as CiA 301 encodes them in heartbeat and node-guarding frames."""

from __future__ import annotations

from enum import IntEnum


class NmtState(IntEnum):
    INITIALISING = 0x00  # only ever seen as the boot-up frame
    STOPPED = 0x04
    OPERATIONAL = 0x05
    PRE_OPERATIONAL = 0x7F

    @property
    def allows_sdo(self) -> bool:
        # MDi-S1-C manual table 2.8: no SDO, PDO, SYNC or EMCY in Stopped
        return self in (NmtState.PRE_OPERATIONAL, NmtState.OPERATIONAL)

    @property
    def allows_pdo(self) -> bool:
        return self is NmtState.OPERATIONAL


class NmtCommand(IntEnum):
    START = 0x01
    STOP = 0x02
    ENTER_PRE_OPERATIONAL = 0x80
    RESET_NODE = 0x81
    RESET_COMMUNICATION = 0x82
