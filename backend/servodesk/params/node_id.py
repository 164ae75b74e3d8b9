"""Guided node-id and bitrate changes: write the drive's own parameter, store, reset, follow.

Each step is recorded as a sentence, so the user sees what was done to the drive even when a
later step fails (a drive that never boots at its new id still has the new id stored).
"""

from __future__ import annotations

import asyncio

import servodesk_data
from servodesk.errors import (
    CommTimeoutError,
    ConfirmationRequiredError,
    InvalidValueError,
)
from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import (
    BitrateChangeResult,
    BitrateOptions,
    NodeIdChangeResult,
    NodeIdOptions,
)
from servodesk.nodes.access import NodeAccess
from servodesk.params.service import SAVE_ALL, SAVE_SIGNATURE, STORE_PARAMETERS
from servodesk.sdo.service import SdoService
from servodesk.settings import Settings
from servodesk_data import DriveData, NodeIdSource, ObjectRef, format_object_ref
from servodesk_protocol import cob_id

MIN_NODE_ID = 1
MAX_NODE_ID = 127
STORED = 'Stored the parameters (1010h:01 = "save")'


def kbit(bitrate: int) -> str:
    return f"{bitrate // 1000}" if bitrate % 1000 == 0 else f"{bitrate / 1000:g}"


def object_label(data: DriveData, ref: ObjectRef) -> str:
    """`PA-105 (2006:0A)`, or just the object when the catalogue does not name it."""
    for parameter in data.parameters:
        if parameter.object == ref:
            return f"{parameter.name} ({format_object_ref(ref)})"
    return format_object_ref(ref)


class NodeIdService:
    def __init__(self, access: NodeAccess, settings: Settings) -> None:
        self._access = access
        self._settings = settings
        self._sdo = SdoService(access)

    async def change_node_id(self, node: int, new: int, confirm: bool) -> NodeIdChangeResult:
        """Give the drive at `node` the id `new`: write, store, reset, wait for its boot-up at
        `new`, then move it there in the registry."""
        data, ref = self._node_id_object(node)
        await self._check_target(node, new)
        value, how = await self._node_id_value(node, new, data, ref)
        if not confirm:
            raise ConfirmationRequiredError(
                f"Changing node {node} to {new} stores the new id and resets the drive: "
                "confirm to go on"
            )
        index, subindex = ref
        steps: list[str] = []
        # write, store and reset as one transaction: no other request lands in between
        async with self._access.session(node).exclusive():
            await self._sdo.write(node, index, subindex, value)
            steps.append(f"Wrote {object_label(data, ref)} = {value}{how}")
            await self._store(node)
            steps.append(STORED)
            # Listen before resetting: the boot-up at the new id may follow the reset at once.
            waiter = asyncio.create_task(self._access.wait_boot(new, self._settings.boot_wait))
            await asyncio.sleep(0)  # let the waiter subscribe
            try:
                await self._access.nmt(node, NmtCommandName.RESET_NODE)
            except BaseException:
                waiter.cancel()
                raise
        steps.append(f"Reset node {node} (NMT reset node)")
        if not await waiter:
            raise CommTimeoutError(
                new,
                f"the reset: no boot-up within {self._settings.boot_wait:g} s. The new id is "
                f"written and stored; power-cycle the drive and scan the bus",
            )
        steps.append(f"Node {new} booted (boot-up message {cob_id.HEARTBEAT + new:03X}h)")
        info = await self._access.move(node, new)
        steps.append(f"ServoDesk now talks to the drive as node {new}")
        return NodeIdChangeResult(old_node=node, new_node=new, steps=steps, node=info)

    async def bitrate_options(self, node: int) -> BitrateOptions:
        """What the bitrate dialog may offer for `node`: only what its profile can set."""
        data = self._access.profile_data(node)
        label = self._access.info(node).profile_label
        if data is None or not data.quirks.bitrate_objects:
            how = (
                "ServoDesk does not know how this device (generic profile) sets its bitrate"
                if data is None
                else f"{label} sets its bitrate outside CANopen (switches or its own tool)"
            )
            return BitrateOptions(settable=False, supported=[], note=f"{how}.")
        supported = sorted({code.bitrate for code in data.quirks.bitrate_codes}, reverse=True)
        values: dict[ObjectRef, int] = {}
        for ref in data.quirks.bitrate_objects:
            read = await self._sdo.read(node, *ref)
            if isinstance(read.value, int):
                values[ref] = read.value
        listed = ", ".join(f"{kbit(rate)}" for rate in supported)
        return BitrateOptions(
            settable=True,
            supported=supported,
            current=servodesk_data.bitrate_of(data, values),
            note=f"{label} supports {listed} kbit/s.",
        )

    async def change_bitrate(self, node: int, bitrate: int, confirm: bool) -> BitrateChangeResult:
        """Set the drive's bitrate objects for `bitrate` bit/s, store and reset. The drive then
        talks only at the new bitrate: the bus must be reconnected at it."""
        data = self._access.profile_data(node)
        if data is None:
            raise InvalidValueError(
                f"node {node} has a generic profile: ServoDesk does not know how it sets its "
                "bitrate"
            )
        try:
            values = servodesk_data.bitrate_objects(data, bitrate)
        except ValueError as error:
            raise InvalidValueError(str(error)) from None
        if not values:
            raise InvalidValueError(
                f"{data.profile} sets its bitrate outside CANopen (switches or its own tool)"
            )
        if not confirm:
            raise ConfirmationRequiredError(
                f"Changing node {node} to {kbit(bitrate)} kbit/s cuts it off this bus until the "
                "bus is reconnected at that bitrate: confirm to go on"
            )
        steps: list[str] = []
        for ref, value in values.items():
            index, subindex = ref
            await self._sdo.write(node, index, subindex, value)
            steps.append(f"Wrote {object_label(data, ref)} = {value} (0x{value:02X})")
        await self._store(node)
        steps.append(STORED)
        await self._access.nmt(node, NmtCommandName.RESET_NODE)
        steps.append(f"Reset node {node} (NMT reset node)")
        speed = kbit(bitrate)
        steps.append(
            f"The drive now talks at {speed} kbit/s only: reconnect the bus at {speed} kbit/s"
        )
        return BitrateChangeResult(bitrate=bitrate, steps=steps, reconnect_required=True)

    # ------------------------------------------------------------------------------ helpers

    def _node_id_object(self, node: int) -> tuple[DriveData, ObjectRef]:
        data = self._access.profile_data(node)
        ref = None if data is None else data.quirks.node_id_object
        if data is None or ref is None:
            name = "a generic profile" if data is None else data.profile
            raise InvalidValueError(
                f"node {node} ({name}) has no node-id parameter ServoDesk knows: set its id "
                "with the drive's switches or its own tool"
            )
        return data, ref

    async def _check_target(self, node: int, new: int) -> None:
        if not MIN_NODE_ID <= new <= MAX_NODE_ID:
            raise InvalidValueError(f"node id {new} is outside {MIN_NODE_ID}..{MAX_NODE_ID}")
        if new == node:
            raise InvalidValueError(f"the drive already is node {node}")
        # the bus decides, not the list: a listed node may be gone (its id was changed), an
        # unlisted one may be there
        if await self._access.answers(new):
            raise InvalidValueError(
                f"node {new} is already in use on the bus: two nodes with one id break both"
            )

    def node_id_options(self, node: int) -> NodeIdOptions:
        """Whether the wizard can change `node`'s id over CANopen, said before its first step."""
        try:
            data, ref = self._node_id_object(node)
        except InvalidValueError as refusal:
            return NodeIdOptions(settable=False, note=f"{refusal}.")
        label = object_label(data, ref)
        if data.quirks.node_id_source is NodeIdSource.DIP_PLUS_OFFSET:
            note = f"Set with {label}, added to the drive's DIP switch setting."
        else:
            low, high = self._limits(node, data, ref)
            note = f"Set with {label}; node ids {low}..{high}."
        return NodeIdOptions(settable=True, note=note)

    async def _node_id_value(
        self, node: int, new: int, data: DriveData, ref: ObjectRef
    ) -> tuple[int, str]:
        """The value for the node-id object, and how it gives `new` (for the step text)."""
        low, high = self._limits(node, data, ref)
        if data.quirks.node_id_source is not NodeIdSource.DIP_PLUS_OFFSET:
            if not low <= new <= high:
                raise InvalidValueError(
                    f"{object_label(data, ref)} takes {low}..{high}; node {new} is outside"
                )
            return new, ""
        # Kinco: node id = DIP-switch address + offset 2F80h (Kinco manual §5.1)
        index, subindex = ref
        current = await self._sdo.read(node, index, subindex)
        if not isinstance(current.value, int):
            raise InvalidValueError(f"{object_label(data, ref)} read back {current.raw_hex}")
        dip = node - current.value
        offset = new - dip
        if not low <= offset <= high:
            reach_high = min(MAX_NODE_ID, dip + high)
            raise InvalidValueError(
                f"node {new} is out of reach: the DIP switch gives {dip} and the offset "
                f"{object_label(data, ref)} takes {low}..{high}, so ids {dip + low}..{reach_high}. "
                f"Change the DIP switch to reach node {new}"
            )
        return offset, f": DIP switch {dip} + offset {offset} = node {new}"

    def _limits(self, node: int, data: DriveData, ref: ObjectRef) -> tuple[int, int]:
        for parameter in data.parameters:
            if parameter.object == ref:
                return parameter.min, parameter.max
        sub = self._access.od(node).get(*ref)
        low = sub.low if sub is not None and isinstance(sub.low, int) else 0
        high = sub.high if sub is not None and isinstance(sub.high, int) else MAX_NODE_ID
        return low, high

    async def _store(self, node: int) -> None:
        await self._access.session(node).download(
            STORE_PARAMETERS, SAVE_ALL, SAVE_SIGNATURE.to_bytes(4, "little")
        )
