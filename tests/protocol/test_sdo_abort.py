"""SDO abort codes and their CiA 301 meanings."""

from __future__ import annotations

import pytest

from servodesk_protocol import sdo_abort


@pytest.mark.parametrize(
    ("code", "meaning"),
    [
        (sdo_abort.TOGGLE_NOT_ALTERNATED, "Toggle bit not alternated"),
        (sdo_abort.UNSUPPORTED_ACCESS, "Unsupported access to an object"),
        (sdo_abort.READ_ONLY, "Attempt to write a read-only object"),
        (sdo_abort.NO_OBJECT, "Object does not exist in the object dictionary"),
        (sdo_abort.NOT_MAPPABLE, "Object cannot be mapped to the PDO"),
        (
            sdo_abort.PDO_LENGTH_EXCEEDED,
            "The number and length of the objects to be mapped would exceed the PDO length",
        ),
        (sdo_abort.NO_SUBINDEX, "Sub-index does not exist"),
        (sdo_abort.VALUE_TOO_HIGH, "Value of parameter written too high (download only)"),
        (
            sdo_abort.DEVICE_STATE,
            "Data cannot be transferred or stored to the application because of the present "
            "device state",
        ),
        (0x0BADC0DE, "Unknown abort code (vendor-specific or not in CiA 301)"),
    ],
)
def test_describe(code: int, meaning: str) -> None:
    assert sdo_abort.describe(code) == meaning


@pytest.mark.parametrize(
    ("code", "value"),
    [
        (sdo_abort.TOGGLE_NOT_ALTERNATED, 0x05030000),
        (sdo_abort.PROTOCOL_TIMED_OUT, 0x05040000),
        (sdo_abort.UNSUPPORTED_ACCESS, 0x06010000),
        (sdo_abort.WRITE_ONLY, 0x06010001),
        (sdo_abort.READ_ONLY, 0x06010002),
        (sdo_abort.NOT_MAPPABLE, 0x06040041),
        (sdo_abort.PARAMETER_INCOMPATIBLE, 0x06040043),
        (sdo_abort.TYPE_MISMATCH, 0x06070010),
        (sdo_abort.LENGTH_TOO_HIGH, 0x06070012),
        (sdo_abort.LENGTH_TOO_LOW, 0x06070013),
        (sdo_abort.INVALID_VALUE, 0x06090030),
        (sdo_abort.VALUE_TOO_LOW, 0x06090032),
        (sdo_abort.CANNOT_STORE, 0x08000020),
        (sdo_abort.DEVICE_STATE, 0x08000022),
        (sdo_abort.NO_DATA, 0x08000024),
    ],
)
def test_codes(code: int, value: int) -> None:
    assert code == value


def test_every_named_code_has_a_meaning() -> None:
    named = {
        value
        for name, value in vars(sdo_abort).items()
        if name.isupper() and isinstance(value, int)
    }
    assert named == set(sdo_abort.MEANINGS)
