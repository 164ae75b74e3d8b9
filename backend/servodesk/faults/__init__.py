"""Faults: EMCY and fault-object decoding layered over each drive's own alarm table."""

from __future__ import annotations

from servodesk.faults.decode import FaultRecord, decode_emcy, decode_kinco_bits, fault_words

__all__ = ["FaultRecord", "decode_emcy", "decode_kinco_bits", "fault_words"]
