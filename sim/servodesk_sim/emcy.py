"""EMCY producer and fault bookkeeping: 603Fh, 1001h, 1003h, Kinco 2600h:02 and the EMCY frame.

The three EMCY data formats (MDi alarm number, Kinco, CiA 301) are servodesk_protocol.emcy; this
module decides when a drive sends which and keeps the fault objects in step.
"""

from __future__ import annotations

from dataclasses import dataclass

from servodesk_protocol import cob_id
from servodesk_protocol.emcy import (
    COB_ID_EMCY,
    ERROR_HISTORY,
    ERROR_REGISTER,
    EmcyFormat,
    ErrorRegister,
    history_entry,
    make_payload,
)
from servodesk_protocol.sdo_abort import READ_ONLY, VALUE_TOO_HIGH
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.frames import Frame
from servodesk_sim.od_store import ObjectStore, Value

ERROR_CODE = 0x603F  # Error code (CiA 402)
KINCO_FAULTS = 0x2600  # Kinco fault object; sub 2 = Detected_Faults bits (Kinco manual §8)
KINCO_DETECTED_SUB = 2
MAX_HISTORY = 254


@dataclass(frozen=True)
class Fault:
    code: int  # the profile's own number: MDi alarm no., Kinco 603Fh code, cia402 EMCY code
    emcy_code: int  # CiA 301/402 class code, for 1003h (and the EMCY of the CiA 301 format)
    error_register: int  # 1001h bits to set (bit 0 generic is always added)
    kinco_bits: int = 0  # 2600h:02 bit(s) for Kinco (Kinco manual §8 table)


def emcy_payload(fmt: EmcyFormat, fault: Fault | None, error_register: int) -> bytes:
    """Data bytes of an EMCY frame; `fault` None is the "error reset / no error" EMCY.

    MDi and Kinco send the drive's own code, CiA 301 the EMCY class code; manufacturer bytes
    stay zero because the profiles define no extra information.
    """
    if fault is None:
        return make_payload(fmt, 0, 0)
    code = fault.emcy_code if fmt is EmcyFormat.CIA301 else fault.code
    return make_payload(fmt, code, error_register)


class FaultManager:
    """Active faults of one drive, the objects that show them, and the EMCYs announcing them."""

    def __init__(
        self, store: ObjectStore, fmt: EmcyFormat, *, history: bool, kinco_fault_bits: bool
    ) -> None:
        self._store = store
        self._fmt = fmt
        self._active: list[Fault] = []
        self._kinco = kinco_fault_bits and store.has(KINCO_FAULTS, KINCO_DETECTED_SUB)
        self._history_size = 0
        if history and store.has(ERROR_HISTORY, 0):
            while self._history_size < MAX_HISTORY and store.has(
                ERROR_HISTORY, self._history_size + 1
            ):
                self._history_size += 1
            store.add_validator(ERROR_HISTORY, self._check_history_write)
            store.add_write_hook(ERROR_HISTORY, self._history_written)

    @property
    def active(self) -> Fault | None:
        """The most recent active fault, or None when the drive has no fault."""
        return self._active[-1] if self._active else None

    def raise_fault(self, fault: Fault, now: float, *, may_send: bool) -> list[Frame]:
        """Record a fault; the EMCY announcing it (none if it is already active or EMCY is off).

        `now` is the time of the fault (kept in the signature for an EMCY inhibit time, 1015h).
        """
        if any(known.code == fault.code for known in self._active):
            return []  # Kinco manual §5.6: a persisting fault generates one EMCY only
        self._active.append(fault)
        register = self._error_register()
        self._publish(fault.code, register)
        if self._history_size:
            # Nanotec article: the EMCY code and the error register are recorded together.
            self._record(history_entry(fault.emcy_code, register & 0xFF))
        return self._emit(emcy_payload(self._fmt, fault, register), may_send=may_send)

    def clear(self, now: float, *, may_send: bool) -> list[Frame]:
        """Fault reset: 603Fh, 1001h and 2600h:02 back to 0, the "error reset" EMCY; 1003h kept."""
        if not self._active:
            return []  # nothing was announced, so nothing to take back
        self._active.clear()
        self._publish(0, 0)
        return self._emit(emcy_payload(self._fmt, None, 0), may_send=may_send)

    # ------------------------------------------------------------------ objects

    def _error_register(self) -> int:
        register = 0
        for fault in self._active:
            register |= fault.error_register | ErrorRegister.GENERIC
        return register

    def _publish(self, code: int, register: int) -> None:
        store = self._store
        if store.has(ERROR_CODE):
            bits = len(store.variable(ERROR_CODE))
            store.set(ERROR_CODE, 0, code & ((1 << bits) - 1))
        if store.has(ERROR_REGISTER):
            store.set(ERROR_REGISTER, 0, register)
        if self._kinco:
            detected = 0
            for fault in self._active:
                detected |= fault.kinco_bits
            store.set(KINCO_FAULTS, KINCO_DETECTED_SUB, detected)

    def _record(self, entry: int) -> None:
        """Newest entry at sub 1, older ones move down, sub 0 = count (CiA 301 §7.5.2.4)."""
        store = self._store
        count = min(store.get(ERROR_HISTORY, 0) + 1, self._history_size)
        for sub in range(count, 1, -1):
            store.set(ERROR_HISTORY, sub, store.get(ERROR_HISTORY, sub - 1))
        store.set(ERROR_HISTORY, 1, entry)
        store.set(ERROR_HISTORY, 0, count)

    def _check_history_write(self, sub: int, value: Value) -> None:
        if sub != 0:
            raise SdoAbort(READ_ONLY, "1003h entries are read-only")
        if value != 0:
            # Nanotec article SDO abort table, 06090031: "1003h:00 can only be set to 0".
            raise SdoAbort(VALUE_TOO_HIGH, "write 0 to 1003h:00 to clear the history")

    def _history_written(self, _sub: int, _value: Value) -> None:
        for sub in range(1, self._history_size + 1):
            self._store.set(ERROR_HISTORY, sub, 0)

    # ------------------------------------------------------------------ bus

    def _cob_id(self) -> int | None:
        if not self._store.has(COB_ID_EMCY):
            return cob_id.EMCY + self._store.node_id
        cob = self._store.get(COB_ID_EMCY)
        # MDi-S1-C manual §2.7: 1014h bit 31 switches the EMCY off
        return None if cob & cob_id.INVALID_BIT else cob & cob_id.CAN_ID_MASK

    def _emit(self, payload: bytes, *, may_send: bool) -> list[Frame]:
        cob_id = self._cob_id()
        if not may_send or cob_id is None:
            return []
        return [Frame(cob_id, payload)]
