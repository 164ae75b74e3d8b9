"""Named drive parameters (PA-14, PA-106, Node offset …) from the profile's catalogue, and the
store / restore-defaults commands (1010h / 1011h).

A value is checked against the catalogue's range and choices before anything is written, and the
answer says when the change takes effect, because a bitrate or node-id change that seems to do
nothing is the classic commissioning trap.
"""

from __future__ import annotations

import builtins
import re

from servodesk.audit.entry import current_entry
from servodesk.errors import (
    ConfirmationRequiredError,
    InvalidValueError,
    SdoAbortError,
    ServodeskError,
)
from servodesk.events.bus import BusEvent, EventKind
from servodesk.events.texts import say
from servodesk.events.tool_writes import Publish, tool_write, where
from servodesk.models.common import MessageResult
from servodesk.models.params import Param, ParamWriteResult
from servodesk.nodes.access import NodeAccess
from servodesk.sdo import codec
from servodesk.sdo.service import SdoService
from servodesk_data import DriveData, Parameter, TakesEffect, format_object_ref

STORE_PARAMETERS = 0x1010  # Store parameters
RESTORE_DEFAULTS = 0x1011  # Restore default parameters
SAVE_ALL = 1  # sub-index: all parameters
SAVE_SIGNATURE = 0x65766173  # "save" in ASCII, little-endian (CiA 301 §7.5.2.13)
LOAD_SIGNATURE = 0x64616F6C  # "load" in ASCII, little-endian (CiA 301 §7.5.2.14)

APPLIED = "applied"
AFTER_RESET = "takes effect after reset: store the parameters (1010h), then reset the node"
_INT_TEXT = re.compile(r"([+-]?)(0[xX][0-9A-Fa-f]+|[0-9]+)")


def effect_message(takes_effect: TakesEffect) -> str:
    if takes_effect is TakesEffect.IMMEDIATELY:
        return APPLIED
    # after_reset and after_store_and_reset read alike: a reset node (or power cycle) reloads
    # the stored set (MDi-S1-C manual §2.3.1), so a change that waits for a reset must be stored
    # first
    return AFTER_RESET


def choice_text(parameter: Parameter) -> str:
    return ", ".join(f"{code} ({label})" for code, label in sorted(parameter.choices.items()))


def resolve_value(parameter: Parameter, value: int | str) -> int:
    """A number or a choice (its label or its number as text) -> the code to write, checked
    against the catalogue's range and choices. InvalidValueError names what is allowed."""
    if isinstance(value, str):
        text = value.strip()
        labels = {label.strip().lower(): code for code, label in parameter.choices.items()}
        if text.lower() in labels:
            number = labels[text.lower()]
        elif (match := _INT_TEXT.fullmatch(text)) is not None:
            sign, digits = match.groups()
            magnitude = int(digits, 16) if digits[:2].lower() == "0x" else int(digits)
            number = -magnitude if sign == "-" else magnitude
        else:
            allowed = (
                f"one of {choice_text(parameter)}"
                if parameter.choices
                else f"a whole number {parameter.min}..{parameter.max}"
            )
            raise InvalidValueError(f"{parameter.name}: '{value}' is not {allowed}")
    else:
        number = int(value)
    if not parameter.min <= number <= parameter.max:
        unit = f" {parameter.unit}" if parameter.unit else ""
        raise InvalidValueError(
            f"{parameter.name}: {number} is out of range; allowed {parameter.min}..{parameter.max}"
            f"{unit}"
        )
    if parameter.choices and number not in parameter.choices:
        raise InvalidValueError(
            f"{parameter.name}: {number} is not an allowed setting; choose one of "
            f"{choice_text(parameter)}"
        )
    return number


class ParamService:
    def __init__(self, access: NodeAccess, *, publish: Publish | None = None) -> None:
        self._access = access
        self._sdo = SdoService(access)
        self._publish = publish  # "tool-write" events on the timeline
        # parameters written since the node's last boot-up that take effect only after a reset:
        # the drive reads back the new value, but still works with the old one
        self._pending: dict[int, set[str]] = {}

    def on_node_event(self, event: BusEvent) -> None:
        """A boot-up: the node now works with what it had stored; nothing is pending."""
        if event.kind is EventKind.BOOT_UP and event.node is not None:
            self._pending.pop(event.node, None)

    def catalogue(self, node: int) -> tuple[Parameter, ...]:
        data = self._access.profile_data(node)
        return () if data is None else data.parameters

    async def list(self, node: int) -> builtins.list[Param]:
        """Every catalogue parameter with its value read from the drive; a parameter the drive
        refuses to read carries the abort in `error` instead of failing the list."""
        return [await self._read(node, parameter) for parameter in self.catalogue(node)]

    async def get(self, node: int, name: str) -> Param:
        return await self._read(node, self._parameter(node, name))

    async def set(self, node: int, name: str, value: int | str) -> ParamWriteResult:
        parameter = self._parameter(node, name)
        number = resolve_value(parameter, value)
        index, subindex = parameter.object
        entry = current_entry()
        audited = entry is not None and entry.records_object()
        # an audited write reads the old value once, for its entry; the timeline takes it there
        old = None
        if self._publish is not None and not audited:
            old = await self._old_value(node, parameter)
        written = await self._sdo.write(node, index, subindex, number)
        if audited and entry is not None and isinstance(entry.old, int):
            old = entry.old
        if entry is not None and entry.action == "param":
            was = f"{entry.old} → " if entry.old is not None else ""
            entry.what = (
                f"set {parameter.name} ({where(index, subindex)}) of node {node}: "
                f"{was}{written.value}"
            )
        if self._publish is not None:
            self._publish(
                tool_write(
                    node,
                    say(
                        "event.param_set" if old is None else "event.param_set_was",
                        name=parameter.name,
                        where=where(index, subindex),
                        node=node,
                        value=str(written.value),
                        **({} if old is None else {"old": old}),
                    ),
                    "param",
                    name=parameter.name,
                    index=index,
                    subindex=subindex,
                    old=old,
                    value=written.value,
                )
            )
        changed = parameter.takes_effect is not TakesEffect.IMMEDIATELY
        if changed:
            self._pending.setdefault(node, set()).add(parameter.name)
        param = self._param(parameter, written.value if isinstance(written.value, int) else None)
        return ParamWriteResult(
            param=param.model_copy(update={"pending": changed}),
            message=self._effect(node, parameter),
            requires_reset=changed,
            requires_store=changed,
        )

    async def store(self, node: int, confirm: bool) -> MessageResult:
        if not confirm:
            raise ConfirmationRequiredError(
                "Storing overwrites the parameters saved in the drive: confirm to go on"
            )
        data = SAVE_SIGNATURE.to_bytes(4, "little")
        await self._access.session(node).download(STORE_PARAMETERS, SAVE_ALL, data)
        self._command(node, "store", STORE_PARAMETERS, "event.stored")
        return MessageResult(
            message='parameters stored (1010h:01 = "save"): the drive keeps them over a reset '
            "or power cycle"
        )

    async def restore_defaults(self, node: int, confirm: bool) -> MessageResult:
        if not confirm:
            raise ConfirmationRequiredError(
                "Restoring defaults discards the parameters saved in the drive: confirm to go on"
            )
        data = LOAD_SIGNATURE.to_bytes(4, "little")
        await self._access.session(node).download(RESTORE_DEFAULTS, SAVE_ALL, data)
        self._command(node, "restore-defaults", RESTORE_DEFAULTS, "event.defaults_restored")
        return MessageResult(
            message='default parameters restored (1011h:01 = "load"); takes effect after reset: '
            "reset the node"
        )

    def _command(self, node: int, action: str, index: int, message_id: str) -> None:
        if self._publish is not None:
            said = say(message_id, node=node)
            self._publish(tool_write(node, said, action, index=index, subindex=SAVE_ALL))

    async def _old_value(self, node: int, parameter: Parameter) -> int | None:
        """The value before a write, for the timeline (best effort: None when unreadable)."""
        try:
            return (await self._read(node, parameter)).value
        except ServodeskError:
            return None

    def _parameter(self, node: int, name: str) -> Parameter:
        data: DriveData | None = self._access.profile_data(node)
        if data is None:
            raise InvalidValueError(f"node {node} has no parameter catalogue (generic profile)")
        for parameter in data.parameters:
            if parameter.name == name:
                return parameter
        known = ", ".join(p.name for p in data.parameters)
        raise InvalidValueError(f"{data.profile} has no parameter '{name}'; known: {known}")

    def _effect(self, node: int, parameter: Parameter) -> str:
        """What the user does next: a bitrate or node-id parameter has its own wizard, which
        also moves the bus or the tool along with the drive."""
        data = self._access.profile_data(node)
        quirks = data.quirks if data is not None else None
        if quirks is not None and parameter.object in quirks.bitrate_objects:
            return (
                "written; the drive talks at the new bitrate after a store and a reset, and the "
                "bus must follow it: use Change bitrate…, which stores, resets and says how to "
                "reconnect"
            )
        if quirks is not None and parameter.object == quirks.node_id_object:
            return (
                "written; the drive answers at the new id after a store and a reset: use Change "
                "node ID…, which stores, resets and follows the drive to its new id"
            )
        return effect_message(parameter.takes_effect)

    async def _read(self, node: int, parameter: Parameter) -> Param:
        pending = parameter.name in self._pending.get(node, ())
        param = await self._read_value(node, parameter)
        return param.model_copy(update={"pending": True}) if pending else param

    async def _read_value(self, node: int, parameter: Parameter) -> Param:
        index, subindex = parameter.object
        try:
            data = await self._access.session(node).upload(index, subindex)
        except SdoAbortError as abort:
            return self._param(parameter, None, f"SDO abort {abort.code_hex}: {abort.meaning}")
        sub = self._access.od(node).get(index, subindex)
        value = codec.decode(sub, data) if sub is not None else codec.decode_unknown(data)
        if not isinstance(value, int):
            return self._param(parameter, None, f"unexpected answer {codec.hex_bytes(data)}")
        return self._param(parameter, value)

    @staticmethod
    def _param(parameter: Parameter, value: int | None, error: str | None = None) -> Param:
        index, subindex = parameter.object
        return Param(
            name=parameter.name,
            label=parameter.label,
            description=parameter.description,
            object=format_object_ref(parameter.object),
            index=index,
            subindex=subindex,
            value=value,
            unit=parameter.unit,
            min=parameter.min,
            max=parameter.max,
            default=parameter.default,
            takes_effect=parameter.takes_effect.value,
            choices={str(code): label for code, label in sorted(parameter.choices.items())},
            error=error,
        )
