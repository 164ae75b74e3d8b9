"""Received PDO payloads decoded with the shipped dictionaries: the values a scope would show."""

from __future__ import annotations

import re
import struct
from dataclasses import replace

import pytest

from servodesk.od import ObjectDictionaryModel
from servodesk.pdo.decode import Field, PdoDecoder, statusword_text, value_text
from servodesk.pdo.model import MappedObject
from tests.backend.test_pdo_validate import dictionary


def obj(index: int, subindex: int, bits: int) -> MappedObject:
    return MappedObject(index, subindex, bits)


def with_types(od: ObjectDictionaryModel) -> ObjectDictionaryModel:
    """The MDi-S1-C dictionary plus objects of the types the shipped drives do not use."""
    template = od.objects[0x60FE]  # Digital outputs record: give it one sub-index per type
    subs = dict(template.subs)
    for sub, (name, data_type) in enumerate(
        [
            ("Flag", 0x0001),  # BOOLEAN
            ("Gain", 0x0008),  # REAL32
            ("Offset", 0x0010),  # INTEGER24
            ("Counter", 0x0016),  # UNSIGNED24
            ("Energy", 0x0011),  # REAL64
            ("Big", 0x0015),  # INTEGER64
        ],
        start=2,
    ):
        subs[sub] = replace(template.subs[1], subindex=sub, name=name, data_type=data_type, unit="")
    return replace(od, objects={**od.objects, 0x60FE: replace(template, subs=subs)})


MDI_TPDO1 = (obj(0x6041, 0, 16), obj(0x6064, 0, 32), obj(0x6061, 0, 8))


@pytest.mark.parametrize(
    ("profile", "mapping", "data", "expected"),
    [
        (  # statusword 0637h "operation enabled", position -1000, mode 1 (PP)
            "mdi-s1c",
            MDI_TPDO1,
            bytes.fromhex("3706") + (-1000).to_bytes(4, "little", signed=True) + b"\x01",
            [
                ("Statusword", 0x0637, 0x0637, ""),
                ("Position actual value", -1000, 0xFFFFFC18, "user units"),
                ("Modes of operation display", 1, 1, ""),
            ],
        ),
        (  # mode display -3 is negative (INTEGER8), torque -12.5 % (INTEGER16, 0.1 %)
            "kinco",
            (obj(0x6061, 0, 8), obj(0x6077, 0, 16), obj(0x606C, 0, 32)),
            b"\xfd" + (-125).to_bytes(2, "little", signed=True) + (3000).to_bytes(4, "little"),
            [
                ("Modes of operation display", -3, 0xFD, ""),
                ("Torque actual value", -125, 0xFF83, "0.1 %"),
                ("Velocity actual value", 3000, 3000, "rpm"),
            ],
        ),
        (  # unsigned 32-bit with the top bit set stays positive
            "cia402",
            (obj(0x60FD, 0, 32),),
            b"\x00\x00\x00\x80",
            [("Digital inputs", 0x80000000, 0x80000000, "")],
        ),
    ],
)
def test_values_from_the_shipped_dictionaries(
    profile: str,
    mapping: tuple[MappedObject, ...],
    data: bytes,
    expected: list[tuple[str, int, int, str]],
) -> None:
    decoder = PdoDecoder(mapping, dictionary(profile))
    decoded = decoder.decode(data)
    assert [(d.name, d.value, d.raw, d.unit) for d in decoded] == expected
    assert decoder.values(data) == [value for _, value, _, _ in expected]


@pytest.mark.parametrize(
    ("mapping", "data", "value"),
    [
        ((obj(0x60FE, 2, 1),), b"\x01", True),
        ((obj(0x60FE, 2, 8),), b"\x00", False),
        ((obj(0x60FE, 3, 32),), struct.pack("<f", -2.5), -2.5),
        ((obj(0x60FE, 4, 24),), (-70000).to_bytes(3, "little", signed=True), -70000),
        ((obj(0x60FE, 5, 24),), b"\xff\xff\xff", 0xFFFFFF),
        ((obj(0x60FE, 6, 64),), struct.pack("<d", 1e-3), 1e-3),
        ((obj(0x60FE, 7, 64),), (-(2**40)).to_bytes(8, "little", signed=True), -(2**40)),
    ],
)
def test_every_data_type(mapping: tuple[MappedObject, ...], data: bytes, value: object) -> None:
    [decoded] = PdoDecoder(mapping, with_types(dictionary("mdi-s1c"))).decode(data)
    assert decoded.value == value
    assert type(decoded.value) is type(value)


def test_bit_fields_and_dummies_keep_their_place() -> None:
    # a 1-bit flag, an 8-bit INTEGER8 dummy (dropped), a signed 16-bit torque: offsets 0, 1, 9
    mapping = (obj(0x60FE, 2, 1), obj(0x0002, 0, 8), obj(0x6077, 0, 16))
    decoder = PdoDecoder(mapping, with_types(dictionary("mdi-s1c")))
    assert [(f.name, f.bit_offset, f.bits) for f in decoder.fields] == [
        ("Flag", 0, 1),
        ("Torque actual value", 9, 16),
    ]
    payload = 1 | (0xAB << 1) | ((-2 & 0xFFFF) << 9)
    decoded = decoder.decode(payload.to_bytes(4, "little"))
    assert [d.value for d in decoded] == [True, -2]


def test_unknown_objects_decode_raw_unsigned() -> None:
    mapping = (obj(0x2001, 1, 16), MappedObject(0x6064, 0, 32, "Position actual value"))
    decoder = PdoDecoder(mapping, None)
    assert decoder.fields[0] == Field(0x2001, 1, None, 0, 16, None, "")
    decoded = decoder.decode(b"\xff\xff\xff\xff\xff\xff\x00\x00")  # longer frames are fine
    assert [(d.name, d.value) for d in decoded] == [
        (None, 0xFFFF),
        ("Position actual value", 0xFFFFFFFF),
    ]


def test_a_short_frame_is_refused_with_the_mapping_named() -> None:
    decoder = PdoDecoder(MDI_TPDO1, dictionary("mdi-s1c"))
    message = (
        "PDO frame has 3 byte(s) but its mapping needs 7 (56 bits: 6041h:00 Statusword,"
        " 6064h:00 Position actual value, 6061h:00 Modes of operation display)"
    )
    with pytest.raises(ValueError, match=re.escape(message)):
        decoder.decode(b"\x37\x06\x00")


@pytest.mark.parametrize(
    ("index", "value", "text"),
    [
        (0x6041, 0x0250, "Switch on disabled · voltage enabled"),  # 592: a standing drive
        (0x6041, 0x0637, "Operation enabled · voltage enabled · target reached"),
        (0x6041, 0x0218, "Fault · voltage enabled"),
        (0x6041, 0x1637, "Operation enabled · voltage enabled · target reached · mode bit 12"),
        (0x6041, 0x00A0, "Not ready to switch on · warning"),
        (0x6061, 1, "Profile position (PP)"),
        (0x6060, -3, "manufacturer-specific (-3)"),
        (0x6064, 1000, None),  # no words for a position
    ],
)
def test_values_in_words(index: int, value: int, text: str | None) -> None:
    assert value_text(index, 0, value) == text


def test_a_statusword_pattern_that_is_no_state_says_so() -> None:
    assert statusword_text(0x0011) == "no CiA 402 state · voltage enabled"


def test_raw_is_the_fields_bytes_in_frame_order() -> None:
    decoder = PdoDecoder(MDI_TPDO1, dictionary("mdi-s1c"))
    data = bytes.fromhex("5002") + (-1000).to_bytes(4, "little", signed=True) + b"\x01"
    raws = [decoded.raw_bytes.hex(" ").upper() for decoded in decoder.decode(data)]
    assert raws == ["50 02", "18 FC FF FF", "01"]
