"""One simulated drive: the CANopen services and the axis of one node, composed.

`SimDrive` is a pure state machine driven by `on_frame` and `poll` with explicit time, so the
same object runs on a real bus (runner.SimBus) and in exact-frame tests without threads.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path

import canopen

import servodesk_data
from servodesk_data import DriveData, FaultEntry
from servodesk_protocol import cob_id
from servodesk_protocol.emcy import EmcyFormat
from servodesk_protocol.nmt import (
    CONSUMER_HEARTBEAT_TIME,
    PRODUCER_HEARTBEAT_TIME,
    NmtCommand,
    NmtState,
)
from servodesk_protocol.sdo_abort import INVALID_VALUE
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.emcy import Fault, FaultManager
from servodesk_sim.error_control import HeartbeatConsumer, HeartbeatProducer, NodeGuarding
from servodesk_sim.fault_kind import FaultKind
from servodesk_sim.frames import Frame
from servodesk_sim.motion import MotionCore
from servodesk_sim.nmt import NmtSlave
from servodesk_sim.od_store import SIM_FORGET_AT_STORE, ObjectStore, Value
from servodesk_sim.pdo import PdoEngine
from servodesk_sim.profile_config import DriveConfig, drive_config
from servodesk_sim.sdo_server import SdoServer
from servodesk_sim.sync import SyncProducer

log = logging.getLogger(__name__)

CONTROL_PERIOD = 0.001  # s: the axis runs at a fixed 1 kHz so it is deterministic
# The runner polls once per control period with some jitter. A SYNC due within half a period
# is sent at this poll rather than one whole period late, so the two clocks cannot alias into
# alternating 0 ms / 2 ms SYNC periods.
SYNC_LEAD = CONTROL_PERIOD / 2
# A real drive's control loop never stalls; this one runs on a thread of a busy computer (two
# test workers and a build beside it) and may be polled tens of milliseconds late. It runs the
# periods it missed, so ramps and heartbeat-timed stops keep wall-clock time; after a longer
# stall (a debugger, a suspended laptop) the rest of the time is dropped, not run in one burst.
CATCH_UP_LIMIT_S = 0.25
MAX_STEPS_PER_POLL = round(CATCH_UP_LIMIT_S / CONTROL_PERIOD)


class SimDrive:
    """A simulated CANopen drive of one profile at one node id."""

    def __init__(self, data: DriveData, node_id: int, *, bus_bitrate: int | None = None) -> None:
        if not 1 <= node_id <= 127:
            raise ValueError(f"node id {node_id} is outside 1–127")
        self.data = data
        self.config: DriveConfig = drive_config(data)
        od = _dictionary(_file_key(servodesk_data.eds_path(data.identity.name)), node_id)
        self.store = ObjectStore(od, node_id, length_check=self.config.length_check)
        self._commission_node_id(node_id)
        self._node_id = node_id
        # Each simulated drive gets its own serial number, so two drives of one profile are told
        # apart by 1018h as real ones are; it is the device's, kept through resets and new ids.
        self._serial = 0x53440000 + node_id
        self._keep_serial()
        # The bus runs at the bitrate the drive was commissioned for unless told otherwise.
        self.bus_bitrate = bus_bitrate if bus_bitrate is not None else self._configured_bitrate()
        if bus_bitrate is not None:
            self._commission_bitrate(bus_bitrate)

        self.nmt = NmtSlave()
        self.sdo = SdoServer(self.store, block_transfer=self.config.sdo_block_transfer)
        self.heartbeat = HeartbeatProducer()
        self.consumer = HeartbeatConsumer()
        self.guarding = NodeGuarding()
        self.pdo = PdoEngine(self.store, self.config.pdo_rules, lambda: self.nmt.state)
        self.sync = SyncProducer(self.store, self.config.sync_rules, lead=SYNC_LEAD)
        self.faults = FaultManager(
            self.store,
            self.config.emcy_format,
            history=self.config.fault_history,
            kinco_fault_bits=self.config.kinco_fault_bits,
        )
        self._pending_kinds: list[FaultKind] = []
        self.motion = self._new_motion()
        self._out: list[Frame] = []  # frames produced inside hooks, sent with the next answer
        self._now = 0.0
        self._last_step: float | None = None
        self._step_debt = 0.0
        self._silent = False  # configured for another bitrate than the bus: hears and says nothing
        self._install_hooks()

    def _new_motion(self) -> MotionCore:
        return MotionCore(
            self.store,
            self.config.motion,
            on_fault=self._pending_kinds.append,
            fault_reset=self._fault_reset,
        )

    # ----------------------------------------------------------------------------- identity

    @property
    def node_id(self) -> int:
        return self._node_id

    @property
    def profile(self) -> str:
        return self.data.identity.name

    @property
    def silent(self) -> bool:
        """True while the drive's bitrate differs from the bus's (it cannot take part)."""
        return self._silent

    def _commission_node_id(self, node_id: int) -> None:
        """Set the drive's own node-id parameter so it boots at `node_id` (as if commissioned)."""
        # Kinco: the DIP switch gives the address and 2F80h adds an offset (Kinco manual §5.1), so a
        # drive started at `node_id` has its DIP switch there and offset 0.
        self._dip_node_id = node_id
        cfg = self.config
        if cfg.node_id_object is None:
            return
        index, sub = cfg.node_id_object
        value = 0 if cfg.node_id_source == "dip_plus_offset" else node_id
        self.store.set(index, sub, value)
        self.store.commit_stored(index, sub)

    def _commission_bitrate(self, bitrate: int) -> None:
        """Set the drive's bitrate objects to `bitrate` (as if commissioned for this bus)."""
        for (index, sub), value in servodesk_data.bitrate_objects(self.data, bitrate).items():
            self.store.set(index, sub, value)
            self.store.commit_stored(index, sub)

    def _configured_node_id(self) -> int:
        cfg = self.config
        if cfg.node_id_object is None:
            return self._node_id
        index, sub = cfg.node_id_object
        value = self.store.get(index, sub)
        if cfg.node_id_source == "dip_plus_offset":
            value += self._dip_node_id
        return value if 1 <= value <= 127 else self._node_id

    def _configured_bitrate(self) -> int | None:
        values = {ref: self.store.get(*ref) for ref in self.config.bitrate_objects}
        return servodesk_data.bitrate_of(self.data, values)

    # ----------------------------------------------------------------------------- hooks

    def _install_hooks(self) -> None:
        store = self.store
        store.add_write_hook(0x6040, lambda _sub, value: self._controlword(value))  # Controlword
        store.add_write_hook(0x5FF0, lambda _sub, value: self._inject(value))  # SIM inject fault
        if store.has(SIM_FORGET_AT_STORE):  # refused before it is kept: only storable entries
            store.add_validator(SIM_FORGET_AT_STORE, self._forget_at_store)
        if store.has(CONSUMER_HEARTBEAT_TIME):
            store.add_validator(CONSUMER_HEARTBEAT_TIME, self._validate_consumers)
            store.add_write_hook(
                CONSUMER_HEARTBEAT_TIME, lambda _sub, _value: self._configure_consumers()
            )
        store.add_write_hook(
            PRODUCER_HEARTBEAT_TIME, lambda _sub, _value: self.heartbeat.restart(self._now)
        )
        for index, sub in self.data.quirks.enumerated_objects:
            allowed = self._choices_of(index, sub)
            store.add_validator(index, self._enumerated_validator(sub, allowed))
        quirks = self.data.quirks
        if quirks.unsupported_mode_display is None and store.has(0x6060):
            # Drives that do not show an unsupported mode as 0 in 6061h (the MDi does, MDi-S1-C
            # manual §3.3) refuse it: only the modes of 6502h, or 0 (no mode).
            modes = quirks.supported_modes | {0}
            store.add_validator(0x6060, self._enumerated_validator(0, frozenset(modes)))

    def _choices_of(self, index: int, sub: int) -> frozenset[int]:
        for parameter in self.data.parameters:
            if parameter.object == (index, sub):
                return frozenset(parameter.choices)
        raise ValueError(f"{self.profile}: {index:04X}h:{sub} has no catalogue choices")

    @staticmethod
    def _enumerated_validator(sub: int, allowed: frozenset[int]) -> Callable[[int, Value], None]:
        def check(written_sub: int, value: Value) -> None:
            if written_sub == sub and value not in allowed:
                listed = ", ".join(str(v) for v in sorted(allowed))
                raise SdoAbort(INVALID_VALUE, f"allowed values: {listed}")

        return check

    def _controlword(self, value: Value) -> None:
        if isinstance(value, int):
            self.motion.on_controlword(value)
            self._settle_faults()

    def _inject(self, value: Value) -> None:
        if isinstance(value, int) and value != 0:
            self._raise(self._fault_for_code(value))

    def _forget_at_store(self, _sub: int, value: Value) -> None:
        if isinstance(value, int) and value != 0:
            self.store.forget_at_next_store(value >> 8, value & 0xFF)

    def _consumer_entries(self) -> list[int]:
        count = self.store.get(CONSUMER_HEARTBEAT_TIME, 0)
        return [self.store.get(CONSUMER_HEARTBEAT_TIME, sub) for sub in range(1, count + 1)]

    def _validate_consumers(self, sub: int, value: Value) -> None:
        entries = self._consumer_entries()
        if isinstance(value, int) and 1 <= sub <= len(entries):
            entries[sub - 1] = value
        self.consumer.validate(entries)

    def _configure_consumers(self) -> None:
        self.consumer.configure(self._consumer_entries())

    # ----------------------------------------------------------------------------- faults

    def _fault_for_code(self, code: int) -> Fault:
        entry = self.data.fault(code)
        if entry is None:
            # An unlisted code still faults the drive, as an unlisted alarm would. Kinco and
            # CiA 402 codes are EMCY codes themselves; an MDi alarm number is not (generic 1000h).
            alarm_numbers = self.config.emcy_format is EmcyFormat.ALARM_NUMBER
            emcy_code = 0x1000 if alarm_numbers else code & 0xFFFF
            return Fault(code=code, emcy_code=emcy_code, error_register=0x01)
        return _fault_of(entry)

    def _fault_for_kind(self, kind: FaultKind) -> Fault:
        entry = self.data.fault_for_kind(kind)
        if entry is None:
            return Fault(code=0x1000, emcy_code=0x1000, error_register=0x01)
        return _fault_of(entry)

    def _raise(self, fault: Fault) -> None:
        already = self.faults.active is not None
        self._out += self.faults.raise_fault(fault, self._now, may_send=self._may_emcy())
        if not already:
            self.motion.enter_fault()

    def _settle_faults(self) -> None:
        """Faults the axis detected are raised after its call returns (no re-entry)."""
        while self._pending_kinds:
            kind = self._pending_kinds.pop(0)
            if kind not in self.data.quirks.status_only_kinds:
                self._raise(self._fault_for_kind(kind))

    def _fault_reset(self) -> bool:
        self._out += self.faults.clear(self._now, may_send=self._may_emcy())
        return True

    def _may_emcy(self) -> bool:
        return self.nmt.state in (NmtState.PRE_OPERATIONAL, NmtState.OPERATIONAL)

    # ----------------------------------------------------------------------------- bus side

    def boot(self, now: float) -> list[Frame]:
        """Power on: load stored parameters, send the boot-up frame, enter Pre-operational."""
        self._now = now
        self._last_step = now
        self._node_id = self._configured_node_id()
        self._silent = self._configured_bitrate() not in (None, self.bus_bitrate)
        self.heartbeat.restart(now)
        self._configure_consumers()
        if self._silent:
            log.info("node %d: bitrate differs from the bus; staying silent", self._node_id)
            return []
        return [self.nmt.boot(self._node_id)]

    def on_frame(self, frame: Frame, now: float) -> list[Frame]:
        self._now = now
        if self._silent:
            return []
        out = self._dispatch(frame, now)
        return self._flush(out)

    def _dispatch(self, frame: Frame, now: float) -> list[Frame]:
        can_id = frame.can_id
        state = self.nmt.state
        if can_id == cob_id.NMT and not frame.rtr:
            return self._nmt_command(frame, now)
        if can_id == cob_id.HEARTBEAT + self._node_id:
            return [self.guarding.on_rtr(state, self._node_id, now)] if frame.rtr else []
        if cob_id.HEARTBEAT < can_id <= cob_id.HEARTBEAT + cob_id.MAX_NODE_ID and not frame.rtr:
            self.consumer.on_heartbeat(can_id - cob_id.HEARTBEAT, now)
            return []
        if not state.allows_sdo:  # Stopped: only NMT and error control (MDi-S1-C manual table 2.8)
            return []
        if can_id == cob_id.SDO_RX + self._node_id and not frame.rtr:
            replies = self.sdo.on_request(frame.data, now)
            self._settle_faults()
            return [Frame(cob_id.SDO_TX + self._node_id, reply) for reply in replies]
        if can_id == self.sync.cob_id() and not frame.rtr:
            return self._on_sync(frame.data, now)
        return self.pdo.on_frame(frame, now) or []

    def _on_sync(self, data: bytes, now: float) -> list[Frame]:
        counter = data[0] if data else None
        self.motion.on_sync()
        return self.pdo.on_sync(counter, now) if self.nmt.state.allows_pdo else []

    def _nmt_command(self, frame: Frame, now: float) -> list[Frame]:
        before = self.nmt.state
        command = self.nmt.on_command(frame.data, self._node_id)
        if command is NmtCommand.RESET_NODE:
            return self._reset(now, node=True)
        if command is NmtCommand.RESET_COMMUNICATION:
            return self._reset(now, node=False)
        if self.nmt.state is not before:
            return self.pdo.on_nmt_state(self.nmt.state, now)
        return []

    def _reset(self, now: float, *, node: bool) -> list[Frame]:
        """Reset node / reset communication: stored values back, new node id and bitrate apply.

        Reset node restarts the whole drive (application and axis: a new motion core reading the
        restored mode objects, faults cleared); reset communication touches only the
        communication area and leaves the axis and its faults as they are (CiA 301 §7.3.2.2).
        """
        if node:
            self.motion.disable()
            self.store.reset_node()
            self.faults.clear(now, may_send=False)
            self._pending_kinds.clear()
            self.motion = self._new_motion()
        new_id = self._configured_node_id()
        self.store.reset_communication(new_id)
        self._keep_serial()  # read-only, so not stored: reloading would give the EDS default
        self._node_id = new_id
        self.sdo.reset()
        self.pdo.reset()
        self.sync.reset()
        self.guarding.reset()
        self.nmt = NmtSlave()
        self._out.clear()
        return self.boot(now)

    def _keep_serial(self) -> None:
        if self.store.has(0x1018, 4):  # Identity: serial number
            self.store.set(0x1018, 4, self._serial)

    def poll(self, now: float) -> list[Frame]:
        """Advance timers and the axis to `now`; returns the frames due."""
        self._now = now
        if self._silent:
            return []
        out: list[Frame] = []
        self._step_axis(now)
        state = self.nmt.state
        beat = self.heartbeat.poll(
            now, self.store.get(PRODUCER_HEARTBEAT_TIME), state, self._node_id
        )
        if beat is not None:
            out.append(beat)
        for _node in self.consumer.poll(now):
            self._raise(self._fault_for_kind(FaultKind.HEARTBEAT_LOST))
        if self._life_guarding_lost(now):
            self._raise(self._fault_for_kind(FaultKind.LIFE_GUARD))
        if state.allows_sdo:
            out += [Frame(cob_id.SDO_TX + self._node_id, r) for r in self.sdo.poll(now)]
            sync = self.sync.poll(now)
            if sync is not None:
                # A drive consumes its own SYNC too; the runner never echoes a node's frames back.
                out.append(sync)
                out += self._on_sync(sync.data, now)
        if state.allows_pdo:
            out += self.pdo.poll(now)
        return self._flush(out)

    def _life_guarding_lost(self, now: float) -> bool:
        guard_ms = self.store.get(0x100C) if self.store.has(0x100C) else 0  # Guard time
        factor = self.store.get(0x100D) if self.store.has(0x100D) else 0  # Life time factor
        return self.guarding.poll(
            now, guard_ms, factor, self.store.get(PRODUCER_HEARTBEAT_TIME) != 0
        )

    def _step_axis(self, now: float) -> None:
        if self._last_step is None:
            self._last_step = now
        self._step_debt += now - self._last_step
        self._last_step = now
        steps = 0
        while self._step_debt >= CONTROL_PERIOD and steps < MAX_STEPS_PER_POLL:
            self.motion.step(CONTROL_PERIOD)
            self._settle_faults()
            self._step_debt -= CONTROL_PERIOD
            steps += 1
        if steps == MAX_STEPS_PER_POLL:
            self._step_debt = 0.0

    def _flush(self, out: list[Frame]) -> list[Frame]:
        if self._out:
            out = [*self._out, *out]
            self._out = []
        return out


def _fault_of(entry: FaultEntry) -> Fault:
    return Fault(
        code=entry.code,
        emcy_code=entry.emcy_code,
        error_register=entry.error_register,
        kinco_bits=entry.kinco_bit,
    )


def create_drive(node_id: int, profile: str, *, bus_bitrate: int | None = None) -> SimDrive:
    """A simulated drive of `profile` ("mdi-s1c", "kinco", "cia402") booting at `node_id`."""
    if profile not in servodesk_data.PROFILE_NAMES:
        known = ", ".join(servodesk_data.PROFILE_NAMES)
        raise ValueError(f"unknown drive profile {profile!r}; known: {known}")
    data = _drive_data(_file_key(servodesk_data.data_dir(profile) / "profile.toml"))
    return SimDrive(data, node_id, bus_bitrate=bus_bitrate)


# A drive's EDS and profile.toml are read once per process (per file version): a drive only
# reads its dictionary (the values live in its ObjectStore) and DriveData is frozen. Importing
# the EDS was most of the time simulated drives took to start, and tests start hundreds.
_FileKey = tuple[str, int, int]


def _file_key(path: Path) -> _FileKey:
    stat = path.stat()
    return str(path), stat.st_mtime_ns, stat.st_size


@lru_cache(maxsize=32)
def _dictionary(file: _FileKey, node_id: int) -> canopen.ObjectDictionary:
    return canopen.import_od(file[0], node_id)


@lru_cache(maxsize=16)
def _drive_data(file: _FileKey) -> DriveData:
    return servodesk_data.load_path(Path(file[0]))
