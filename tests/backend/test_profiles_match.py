"""Profile matching by identity, and the dictionaries the profiles give a node."""

from __future__ import annotations

import pytest

from servodesk.profiles import (
    GENERIC_CIA301,
    GENERIC_CIA402,
    ProfileDictionaries,
    load_known,
    match,
)

KNOWN = load_known()


@pytest.mark.parametrize(
    ("device_type", "vendor_id", "product_code", "profile"),
    [
        (0x00000000, 0x00445653, 0x00000001, "mdi-s1c"),  # MDi reports 1000h = 0
        (0x00020192, 0x00000300, 0x00004A44, "kinco"),
        (0x00020192, 0x0000026C, 0x000000C5, "cia402"),
        (None, 0x00445653, 0x00000001, "mdi-s1c"),  # 1000h refused: 1018h decides
        # a shipped vendor with another product: only the device profile is known
        (0x00020192, 0x0000026C, 0x00000099, GENERIC_CIA402),
        (0x00020192, None, None, GENERIC_CIA402),
        (0x00FF0192, 0x12345678, 1, GENERIC_CIA402),  # additional information bits set
        (0x00000192, 0x12345678, 1, GENERIC_CIA402),
        (0x00000191, 0x12345678, 1, GENERIC_CIA301),  # CiA 401 I/O
        (0x01920000, 0x12345678, 1, GENERIC_CIA301),  # 402 in the high word is not 402
        (None, None, None, GENERIC_CIA301),
        (0x00000000, 0x00445653, None, GENERIC_CIA301),  # product unknown: no guess
    ],
)
def test_match_by_identity(
    device_type: int | None, vendor_id: int | None, product_code: int | None, profile: str
) -> None:
    result = match(device_type, vendor_id, product_code, known=KNOWN)
    assert result.name == profile
    assert result.label
    assert result.eds_path is not None
    assert result.eds_path.is_file()
    assert (result.data is None) == profile.startswith("generic-")


def test_match_loads_the_profiles_itself() -> None:
    assert match(0x00020192, 0x00000300, 0x00004A44).name == "kinco"


def test_generic_dictionaries() -> None:
    dictionaries = ProfileDictionaries()
    cia301 = dictionaries.model(match(0x191, 1, 1, known=KNOWN), 4)
    assert cia301.objects
    assert all(0x1000 <= index <= 0x1FFF for index in cia301.objects)
    assert cia301.get(0x1018, 1) is not None  # Identity: vendor-ID
    cia402 = dictionaries.model(match(0x20192, 1, 1, known=KNOWN), 4)
    assert cia402.get(0x6041) is not None  # Statusword
    assert cia402.get(0x1018, 1) is not None


def test_dictionaries_are_cached_per_node_and_resolved_for_it() -> None:
    dictionaries = ProfileDictionaries()
    mdi = match(0, 0x00445653, 1, known=KNOWN)
    first = dictionaries.model(mdi, 5)
    assert dictionaries.model(mdi, 5) is first
    other = dictionaries.model(mdi, 6)
    cob_5 = first.get(0x1800, 1)  # TPDO1 COB-ID: 180h + node id
    cob_6 = other.get(0x1800, 1)
    assert cob_5 is not None
    assert cob_6 is not None
    assert isinstance(cob_5.default, int)
    assert isinstance(cob_6.default, int)
    assert (cob_5.default & 0x7FF, cob_6.default & 0x7FF) == (0x185, 0x186)
    assert ProfileDictionaries.filename(mdi) == "mdi-s1c/drive.eds"
