"""TPDO payloads decoded a batch at a time with numpy: one frame stream (one COB-ID) in, one
array of raw values per mapped signal out.

The per-frame work of pdo/decode.py (shift, mask, sign, float) done as array operations over
every frame the flush took from the queue: at a saturated bus (~9,000 frames/s) a Python loop
per frame would cost the loop its time; the arrays cost microseconds per batch.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from servodesk.od import datatypes as dt

Floats = npt.NDArray[np.float64]
FRAME_BYTES = 8


@dataclass(frozen=True, slots=True)
class FieldSpec:
    """One signal's place in the payload and how to read it."""

    bit_offset: int
    bits: int
    data_type: int | None  # None: unsigned


def _kind(data_type: int | None, bits: int) -> str:
    if data_type is None:
        return "unsigned"
    if data_type == dt.DataType.BOOLEAN:  # 1 bit, or a whole byte on byte-granular drives
        return "boolean"
    if data_type == dt.DataType.REAL32 and bits == 32:
        return "real32"
    if data_type == dt.DataType.REAL64 and bits == 64:
        return "real64"
    return "signed" if dt.is_signed(data_type) else "unsigned"


class BatchDecoder:
    def __init__(self, fields: Sequence[FieldSpec]) -> None:
        self.fields = tuple(fields)
        self.length = (max((f.bit_offset + f.bits for f in fields), default=0) + 7) // 8
        self._plan = tuple((f.bit_offset, f.bits, _kind(f.data_type, f.bits)) for f in fields)

    def words(self, payloads: Sequence[bytes]) -> npt.NDArray[np.uint64]:
        """Each payload as one little-endian 64-bit word; shorter frames than the mapping
        needs are refused by the caller (`short`)."""
        count = len(payloads)
        if count and all(len(p) == FRAME_BYTES for p in payloads):
            return np.frombuffer(b"".join(payloads), dtype="<u8").astype(np.uint64)
        buf = bytearray(FRAME_BYTES * count)
        for row, payload in enumerate(payloads):  # mixed lengths: pad each to 8 bytes
            buf[row * FRAME_BYTES : row * FRAME_BYTES + min(len(payload), 8)] = payload[:8]
        return np.frombuffer(bytes(buf), dtype="<u8").astype(np.uint64)

    def short(self, payloads: Sequence[bytes]) -> npt.NDArray[np.bool_]:
        """Frames too short for the mapping (a drive sending another mapping than expected)."""
        return np.fromiter((len(p) < self.length for p in payloads), bool, len(payloads))

    def decode(self, words: npt.NDArray[np.uint64]) -> list[Floats]:
        """Raw values per field, as float64 (exact for every integer up to 53 bits)."""
        return [_field(words, offset, bits, kind) for offset, bits, kind in self._plan]


def _field(words: npt.NDArray[np.uint64], offset: int, bits: int, kind: str) -> Floats:
    mask = np.uint64((1 << bits) - 1) if bits < 64 else None
    raw = words if mask is None else (words >> np.uint64(offset)) & mask
    if kind == "real32":
        with np.errstate(invalid="ignore"):  # a signalling NaN widens to NaN, not a warning
            wide: Floats = raw.astype(np.uint32).view(np.float32).astype(np.float64)
        return wide
    if kind == "real64":
        return raw.view(np.float64).copy()
    if kind == "boolean":  # any bit set is true, as pdo/decode.py reads it
        true: Floats = (raw != 0).astype(np.float64)
        return true
    if kind == "signed":
        if bits == 64:
            return raw.view(np.int64).astype(np.float64)
        signed = raw.astype(np.int64)
        sign = np.int64(1 << (bits - 1))
        signed = np.where(signed & sign, signed - (sign << np.int64(1)), signed)
        return signed.astype(np.float64)
    return raw.astype(np.float64)


def strictly_increasing(times: Floats, after: float | None) -> Floats:
    """Arrival times made strictly increasing (a coarse clock can stamp two frames alike):
    each time that does not exceed its predecessor moves 1 µs past it."""
    out = times.copy()
    if after is not None and out.size and out[0] <= after:
        out[0] = after + 1e-6
    bad = np.nonzero(np.diff(out) <= 0)[0]
    for i in bad:  # rare: only ties and steps back
        # a moved time can overtake the times after it (a step back of more than 1 µs):
        # carry on until the original times pass it again
        j = int(i) + 1
        while j < out.size and out[j] <= out[j - 1]:
            out[j] = out[j - 1] + 1e-6
            j += 1
    return out


def sdo_value(data: bytes, data_type: int | None) -> float:
    """An SDO upload's bytes as the raw value (the scope's SDO-polled signals).

    An integer is read from its type's bytes only: an expedited upload that does not indicate
    its size carries 4 bytes whatever the type, the rest undefined (CiA 301). Text, and data
    longer than 8 bytes (domains), have no numeric value: NaN."""
    if data_type == dt.DataType.REAL32 and len(data) >= 4:
        return float(np.frombuffer(data[:4], "<f4")[0])
    if data_type == dt.DataType.REAL64 and len(data) >= 8:
        return float(np.frombuffer(data[:8], "<f8")[0])
    if data_type is not None and dt.is_integer(data_type):
        data = data[: (dt.int_bits(data_type) + 7) // 8]
    elif len(data) > FRAME_BYTES or (data_type is not None and dt.is_text(data_type)):
        return math.nan
    signed = data_type is not None and dt.is_signed(data_type)
    value = int.from_bytes(data, "little", signed=signed)
    return float(value != 0) if data_type == dt.DataType.BOOLEAN else float(value)
