"""Live faults: EMCYs decoded per the node's profile, the active fault per node, the history
(storage), the drive's own history (1003h), 603Fh, and the fault reset.

Everything here runs on the event loop; drive access goes through the node's session (its own
thread). The collector (collector.py) hands each EMCY over from the notifier thread; the 6041h
read that tells the state after an EMCY runs as a background task, one per node at a time:
EMCYs arriving while it runs wait for the next read, so a storm costs a handful of reads, never
one per frame, and the collector never waits for the drive.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from typing import Any

from servodesk.errors import ConfirmationRequiredError, SdoAbortError, ServodeskError
from servodesk.events.bus import EventBus, EventKind, event
from servodesk.events.texts import Said, say
from servodesk.faults.decode import FaultRecord, decode_emcy, fault_words
from servodesk.models.faults import (
    DeviceHistory,
    DeviceHistoryCleared,
    DeviceHistoryEntry,
    Fault,
    FaultResetResult,
    NodeFaults,
)
from servodesk.motion.words import state_label
from servodesk.nodes.registry import NodeRegistry
from servodesk.settings import Settings
from servodesk.storage import Storage
from servodesk_data import DriveData, EmcyFormat
from servodesk_protocol import emcy_codes
from servodesk_protocol.cia402 import (
    CONTROLWORD,
    STATUSWORD,
    Cia402State,
    controlword_bytes,
    decode_state,
    make_fault_reset,
    make_shutdown,
)
from servodesk_protocol.emcy import ERROR_HISTORY, split_history_entry
from servodesk_protocol.sdo_abort import NO_OBJECT, NO_SUBINDEX

NO_SUCH_ENTRY = (NO_OBJECT, NO_SUBINDEX)  # SDO aborts: object / sub-index does not exist

log = logging.getLogger(__name__)

ERROR_CODE = 0x603F  # CiA 402 error code
POLL = 0.02  # s between statusword reads while a fault reset takes effect

ActiveListener = Callable[[int, Fault | None], None]  # (node, its active fault now)


def _is_reset(record: FaultRecord) -> bool:
    return record.source == "cia301" and record.name_en == emcy_codes.RESET_TEXT


def _state(statusword: int) -> Cia402State | None:
    try:
        return decode_state(statusword)
    except ValueError:
        return None


def _label(state: Cia402State | None) -> str | None:
    return state_label(state) if state is not None else None


class FaultService:
    def __init__(
        self, registry: NodeRegistry, events: EventBus, storage: Storage, settings: Settings
    ) -> None:
        self._registry = registry
        self._events = events
        self._storage = storage
        self._settings = settings
        self._active: dict[int, dict[str, Any]] = {}
        self._states: dict[int, Cia402State] = {}
        self._waiting: dict[int, list[dict[str, Any]]] = {}  # faults awaiting their 6041h read
        self._readers: dict[int, asyncio.Task[None]] = {}
        self._listeners: list[ActiveListener] = []

    def add_listener(self, fn: ActiveListener) -> Callable[[], None]:
        """Call `fn(node, fault)` on the loop whenever a node's active fault changes (a new
        EMCY, an error-reset EMCY, a fault reset) and when its EMCYs are stored in the history
        with the state read after them (its active fault then may be unchanged, or none);
        returns its remover."""
        self._listeners.append(fn)

        def remove() -> None:
            if fn in self._listeners:
                self._listeners.remove(fn)

        return remove

    def _set_active(self, node: int, fault: dict[str, Any] | None) -> bool:
        """Change the node's active fault; tells the listeners. Returns whether one was active."""
        had = self._active.pop(node, None) is not None
        if fault is not None:
            self._active[node] = fault
        elif not had:
            return False
        self._notify(node)
        return had

    def _notify(self, node: int) -> None:
        current = self.active(node)
        for fn in list(self._listeners):
            try:
                fn(node, current)
            except Exception:
                log.exception("active-fault listener failed")

    def close(self) -> None:
        for task in self._readers.values():
            task.cancel()
        # what waited for its state read is stored without it
        for faults in self._waiting.values():
            for fault in faults:
                self._storage.add_fault(fault)
        self._waiting.clear()

    # ------------------------------------------------------------------ live (on the loop)

    def on_emcy(self, node: int, data: bytes, when: float) -> None:
        """An EMCY of `node` (handed over by the collector)."""
        profile = self._profile(node)
        record = decode_emcy(profile, node, data, time=when)
        if _is_reset(record):
            if self._set_active(node, None):
                self._events.publish(
                    event(EventKind.FAULT_CLEARED, node, say("event.error_reset", node=node))
                )
            return
        fault = record.as_dict()
        fault["state_before"] = _label(self._states.get(node))
        fault["state_after"] = None
        self._set_active(node, fault)
        self._events.publish(
            event(
                EventKind.EMCY,
                node,
                say("event.emcy", node=node, fault=fault_words(record, profile)),
                fault,
            )
        )
        if not self._registry.known(node):
            self._storage.add_fault(fault)  # nothing to ask: an unidentified node
            return
        self._waiting.setdefault(node, []).append(fault)
        if node not in self._readers:
            task = asyncio.get_running_loop().create_task(self._state_after(node))
            self._readers[node] = task

    def observe_statusword(self, node: int, statusword: int) -> None:
        """Publish hook for anyone who reads 6041h (the motion service, a decoded TPDO): a
        "cia402-state" event when the state differs from the last one seen."""
        state = _state(statusword)
        if state is None:
            return
        previous = self._states.get(node)
        self._states[node] = state
        if previous is not state:
            label = state_label(state)
            said = (
                say("event.state_was", node=node, state=label, was=state_label(previous))
                if previous is not None
                else say("event.state", node=node, state=label)
            )
            self._events.publish(
                event(
                    EventKind.CIA402_STATE,
                    node,
                    said,
                    {"statusword": statusword, "state": state_label(state)},
                )
            )

    async def _state_after(self, node: int) -> None:
        try:
            while self._waiting.get(node):
                faults = self._waiting.pop(node)
                state = await self._read_state(node)
                for fault in faults:
                    fault["state_after"] = _label(state)
                    self._storage.add_fault(fault)
                # the banner shows the state it left; a page listing the history reads it now,
                # even when the fault is no longer active (cleared before its 6041h answer)
                self._notify(node)
        finally:
            self._readers.pop(node, None)

    async def _read_state(self, node: int) -> Cia402State | None:
        try:
            statusword = await self._statusword(node)
        except ServodeskError as error:  # best effort: the fault is stored without it
            log.debug("6041h of node %d after an EMCY: %s", node, error)
            return None
        self.observe_statusword(node, statusword)
        return _state(statusword)

    async def _statusword(self, node: int) -> int:
        raw = await self._registry.session(node).upload(STATUSWORD, 0)
        return int.from_bytes(raw[:2], "little")

    # ------------------------------------------------------------------ queries

    def active(self, node: int) -> Fault | None:
        fault = self._active.get(node)
        return Fault.model_validate(fault) if fault is not None else None

    def all_active(self) -> list[Fault]:
        return [Fault.model_validate(self._active[node]) for node in sorted(self._active)]

    async def node_faults(self, node: int, limit: int, *, all_buses: bool = False) -> NodeFaults:
        """The node's history on the connected bus (node 1 of another bus is another drive),
        or on every bus this data directory has seen."""
        await self._storage.flush()  # every EMCY decoded before the request is in
        bus = None if all_buses else self._storage.bus()
        rows, total = await self._storage.faults(node, limit, bus=bus)
        return NodeFaults(
            active=self.active(node),
            history=[Fault.model_validate(row) for row in rows],
            total=total,
        )

    # ------------------------------------------------------------------ actions on the drive

    async def reset(self, node: int) -> FaultResetResult:
        """Fault reset: controlword bit 7 from 0 to 1 (6040h = 0006h, then 0080h) when the drive
        is in Fault, then the statusword until it leaves Fault (or the transition time)."""
        session = self._registry.session(node)
        before_sw = await self._statusword(node)
        before = _state(before_sw)
        if before is not Cia402State.FAULT:
            self.observe_statusword(node, before_sw)
            label = _label(before) or f"statusword {before_sw:04X}h"
            cleared = self._set_active(node, None)
            said = say(
                "event.not_in_fault_cleared" if cleared else "event.not_in_fault",
                node=node,
                state=label,
            )
            return self._reset_result(node, True, said, before_sw, before_sw)
        await session.download(CONTROLWORD, 0, controlword_bytes(make_shutdown()))
        await session.download(CONTROLWORD, 0, controlword_bytes(make_fault_reset()))
        after_sw = await self._statusword(node)
        deadline = asyncio.get_running_loop().time() + self._settings.motion_transition_timeout
        while (
            _state(after_sw) is Cia402State.FAULT and asyncio.get_running_loop().time() < deadline
        ):
            await asyncio.sleep(POLL)
            after_sw = await self._statusword(node)
        self.observe_statusword(node, after_sw)
        after = _state(after_sw)
        ok = after is not Cia402State.FAULT
        if ok:
            self._set_active(node, None)
            said = say("event.fault_reset_ok", node=node, state=str(_label(after)))
        else:
            said = say("event.fault_reset_failed", node=node, statusword=f"{after_sw:04X}h")
        self._events.publish(event(EventKind.FAULT_RESET, node, said, {"ok": ok}))
        return self._reset_result(node, ok, said, before_sw, after_sw)

    def _reset_result(
        self, node: int, ok: bool, said: Said, before_sw: int, after_sw: int
    ) -> FaultResetResult:
        return FaultResetResult(
            node=node,
            ok=ok,
            message=said.message,
            message_id=said.message_id,
            params=dict(said.params),
            state_before=_label(_state(before_sw)) or "unknown",
            state_after=_label(_state(after_sw)) or "unknown",
            statusword_hex=f"0x{after_sw:04X}",
            active=self.active(node),
        )

    async def device_history(self, node: int) -> DeviceHistory:
        """1003h (the device's own error history, newest first) and 603Fh, decoded."""
        session = self._registry.session(node)
        try:
            count = (await session.upload(ERROR_HISTORY, 0))[0]
        except SdoAbortError as error:
            if error.code not in NO_SUCH_ENTRY:
                raise
            # a drive without 1003h (the MDi-S1-C): no history of its own, 603Fh still told
            error_code, note = await self._error_code(node)
            return DeviceHistory(
                node=node, count=0, entries=[], error_code=error_code, note=note, supported=False
            )
        entries: list[DeviceHistoryEntry] = []
        for sub in range(1, count + 1):
            value = int.from_bytes((await session.upload(ERROR_HISTORY, sub))[:4], "little")
            code, additional = split_history_entry(value)
            data = code.to_bytes(2, "little") + additional.to_bytes(2, "little")
            record = decode_emcy(self._cia301_profile(node), node, data + bytes(4))
            entries.append(
                DeviceHistoryEntry(
                    number=sub, value_hex=f"0x{value:08X}", fault=Fault(**record.as_dict())
                )
            )
        error_code, note = await self._error_code(node)
        return DeviceHistory(
            node=node, count=count, entries=entries, error_code=error_code, note=note
        )

    async def _error_code(self, node: int) -> tuple[Fault | None, str | None]:
        try:
            raw = await self._registry.session(node).upload(ERROR_CODE, 0)
        except ServodeskError as error:
            return None, f"603Fh could not be read: {error}"
        code = int.from_bytes(raw[:2], "little")
        if code == 0:
            return None, None
        record = decode_emcy(self._profile(node), node, code.to_bytes(2, "little"))
        return Fault(**record.as_dict()), None

    async def clear_device_history(self, node: int, *, confirm: bool) -> DeviceHistoryCleared:
        if not confirm:
            raise ConfirmationRequiredError(
                f"clearing node {node}'s error history (1003h) cannot be undone: send "
                '{"confirm": true}'
            )
        await self._registry.session(node).download(ERROR_HISTORY, 0, bytes([0]))
        said = say("event.history_cleared", node=node)
        message = said.message
        self._events.publish(
            event(
                EventKind.TOOL_WRITE,
                node,
                said,
                {"action": "clear-history", "index": ERROR_HISTORY, "subindex": 0},
            )
        )
        return DeviceHistoryCleared(
            node=node, message=message, message_id=said.message_id, params=dict(said.params)
        )

    # ------------------------------------------------------------------ helpers

    def _profile(self, node: int) -> DriveData | None:
        return self._registry.profile_data(node) if self._registry.known(node) else None

    def _cia301_profile(self, node: int) -> DriveData | None:
        """1003h entries hold CiA 301 codes (bits 0–15) whatever the drive's EMCY format."""
        profile = self._profile(node)
        if profile is not None and profile.quirks.emcy_format is EmcyFormat.CIA301:
            return profile
        return None
