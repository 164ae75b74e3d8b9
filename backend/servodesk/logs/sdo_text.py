"""A finished SDO transfer in words: object name from the node's dictionary, value by its type,
abort code with its CiA 301 meaning."""

from __future__ import annotations

from servodesk.logs.context import DecodeContext
from servodesk.logs.events import EventKind
from servodesk.logs.sdo import SdoMode, SdoTransfer
from servodesk.sdo import codec
from servodesk_protocol import cia402, sdo_abort


def transfer_text(
    ctx: DecodeContext, node: int, done: SdoTransfer
) -> tuple[EventKind, str, int | None]:
    """(event kind, text without the node, integer value read or written or None)."""
    where = f"{done.index:04X}:{done.subindex:02X}"
    name = ctx.name(node, done.index, done.subindex)
    obj = f"{where} {name}" if name else where
    verb = "read" if done.upload else "write"
    if done.began_before_log:  # the log holds only the abort
        verb = f"{verb if done.direction_known else 'transfer'} (began before the log)"
    if done.abort is not None:
        side = "the master" if done.aborted_by_client else "the drive"
        meaning = sdo_abort.describe(done.abort)
        text = f"SDO {verb} {obj} aborted by {side}: {done.abort:08X}h {meaning}"
        return EventKind.SDO_ABORT, text, None
    if done.error is not None:
        return EventKind.SDO_ERROR, f"SDO {verb} {obj} {done.error}", None
    sub = ctx.sub(node, done.index, done.subindex)
    value = codec.decode(sub, done.data) if sub is not None else codec.decode_unknown(done.data)
    shown = codec.display_text(sub, value, size=len(done.data))
    if done.size > len(done.data):
        shown = f"{done.data.hex(' ').upper()} … ({done.size} bytes)"
    elif isinstance(value, int) and done.subindex == 0:
        words = _value_words(done.index, value)
        shown = f"{shown} {words}" if words else shown
    mode = "" if done.mode is SdoMode.EXPEDITED else f" ({done.mode.value}, {done.size} bytes)"
    text = f"SDO {verb} {obj} = {shown}{mode}"
    return EventKind.SDO, text, value if isinstance(value, int) else None


def _value_words(index: int, value: int) -> str | None:
    if index == cia402.STATUSWORD:
        return f"[{cia402_state_of(value)}]"
    if index in (cia402.MODES_OF_OPERATION, cia402.MODES_DISPLAY):
        return f"[{cia402.mode_name(value)}]"
    return None


def cia402_state_of(statusword: int) -> str:
    """ "Fault", "Operation enabled" … from 6041h; "no CiA 402 state" for other bit patterns."""
    try:
        return cia402.decode_state(statusword).name.replace("_", " ").capitalize()
    except ValueError:
        return "no CiA 402 state"
