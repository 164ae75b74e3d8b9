"""A decoded PDO value as an engineer reads it: bit fields in hex, scaled units converted.

Pure. The statusword reads 0x0250, not 592 (its bits are what matters); a torque in the
dictionary's unit "0.1 %" reads "12.5 %", not "125 0.1 %".
"""

from __future__ import annotations

import re

# bit fields by their CiA 301 / CiA 402 meaning: every bit is a flag, so hex reads them
HEX_OBJECTS = frozenset(
    {
        (0x1001, 0x00),  # Error register
        (0x603F, 0x00),  # Error code
        (0x6040, 0x00),  # Controlword
        (0x6041, 0x00),  # Statusword
        (0x60FD, 0x00),  # Digital inputs
        (0x60FE, 0x01),  # Digital outputs: physical outputs
    }
)
# a vendor's own words ("Status word", "Control word 2") are bit fields too
_WORD_NAME = re.compile(r"(status|control)\s*word", re.IGNORECASE)
# a unit with a factor in front: "0.1 %", "0.01 rpm", "100 us"
_SCALED = re.compile(r"^\s*(\d+(?:\.\d*)?|\.\d+)\s*([^\d\s].*?)\s*$")


def is_bit_field(index: int, subindex: int, name: str | None) -> bool:
    return (index, subindex) in HEX_OBJECTS or bool(name and _WORD_NAME.search(name))


def unit_scale(unit: str) -> tuple[float, str, int]:
    """(factor, unit, decimals): "0.1 %" -> (0.1, "%", 1); "rpm" -> (1.0, "rpm", 0)."""
    match = _SCALED.match(unit)
    if match is None:
        return 1.0, unit.strip(), 0
    number, rest = match.groups()
    decimals = len(number.split(".")[1]) if "." in number else 0
    return float(number), rest, decimals


def display_text(
    index: int, subindex: int, name: str | None, value: int | float | bool, bits: int, unit: str
) -> str:
    """The value with its unit: "0x0250", "0.0 %", "1200 rpm", "true"."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int) and value >= 0 and is_bit_field(index, subindex, name):
        return f"0x{value:0{max((bits + 3) // 4, 1)}X}"
    factor, shown_unit, decimals = unit_scale(unit)
    if factor != 1.0:
        text = f"{value * factor:.{decimals}f}"
    elif isinstance(value, float):
        text = f"{value:g}"
    else:
        text = str(value)
    return f"{text} {shown_unit}" if shown_unit else text
