"""servodesk_data's loader: object references, bitrate encodings, and clear errors for bad
profile.toml files (file name and key in every message)."""

from __future__ import annotations

from pathlib import Path

import pytest

import servodesk_data
from servodesk_data.fault_kind import FaultKind

# ----------------------------------------------------------------------------- bitrates


@pytest.mark.parametrize(
    ("profile_name", "values", "bitrate"),
    [("mdi-s1c", {(0x2006, 0x0B): code}, rate) for code, rate in enumerate(
        [20_000, 50_000, 100_000, 125_000, 250_000, 500_000, 1_000_000])]
    + [("kinco", {(0x2F81, 0): a, (0x2F82, 0): b}, rate) for a, b, rate in [
        (0x00, 0x14, 1_000_000), (0x00, 0x1C, 500_000), (0x01, 0x1C, 250_000),
        (0x03, 0x1C, 125_000), (0x47, 0x2F, 50_000), (0x53, 0x2F, 20_000)]],
)  # fmt: skip
def test_bitrate_of_and_back(
    profile_name: str, values: dict[tuple[int, int], int], bitrate: int
) -> None:
    data = servodesk_data.load(profile_name)
    assert servodesk_data.bitrate_of(data, values) == bitrate
    assert servodesk_data.bitrate_objects(data, bitrate) == values


@pytest.mark.parametrize(
    ("profile_name", "values"),
    [
        ("mdi-s1c", {(0x2006, 0x0B): 7}),
        ("mdi-s1c", {}),
        ("kinco", {(0x2F81, 0): 0x01, (0x2F82, 0): 0x14}),  # half of one pair, half of another
        ("kinco", {(0x2F81, 0): 0x00}),
        ("cia402", {(0x2006, 0x0B): 5}),
    ],
)
def test_bitrate_of_unknown_setting_is_none(
    profile_name: str, values: dict[tuple[int, int], int]
) -> None:
    assert servodesk_data.bitrate_of(servodesk_data.load(profile_name), values) is None


# ----------------------------------------------------------------------------- loader


@pytest.mark.parametrize(
    ("ref", "parsed"),
    [("2006:08", (0x2006, 0x08)), ("6040:00", (0x6040, 0)), ("2f80:0a", (0x2F80, 10))],
)
def test_parse_object_ref(ref: str, parsed: tuple[int, int]) -> None:
    assert servodesk_data.parse_object_ref(ref) == parsed
    assert servodesk_data.format_object_ref(parsed) == ref.upper()


@pytest.mark.parametrize(
    "ref", ["2006", "2006:8", "2006:008", "20060:08", "0x2006:08", "6040h:00", ""]
)
def test_parse_object_ref_rejects(ref: str) -> None:
    with pytest.raises(ValueError, match="INDEX:SUB"):
        servodesk_data.parse_object_ref(ref)


MINIMAL = """
[identity]
name = "mini"
vendor_id = 1
product_code = 2
device_type = 0x00020192
description = "test drive"
seed = "none"

[quirks]
emcy_format = "cia301"
sdo_block_transfer = false
sdo_length_check = "generic"
pdo_remap_rule = "while_invalid"
pdo_byte_granular = true
rpdo_count = 4
tpdo_count = 4
pdo_rtr_transmission = false
pdo_fixed_cob_ids = 4
sync_min_period_us = 0
sync_require_period_before_enable = false
supported_modes = [1]
homing_methods = [35]
pp_immediate_setpoint = true
homing_reference_found_bit15 = false
max_speed_object = "6080:00"
fault_history_1003 = false
kinco_fault_bits = false
node_id_source = "fixed"
bitrate_objects = []
status_only_kinds = ["homing_error"]
limit_switch_reaction = "fault"

[[parameters]]
name = "Window"
object = "6065:00"
label = "Following error window"
description = "test"
min = 0
max = 500
default = 100
takes_effect = "immediately"

[[faults]]
code = 0x1000
name = "Generic"
name_en = "Generic"
description = "test"
what_to_check = "test"
emcy_code = 0x1000
error_register = 0x01
kinds = ["overspeed", "following_error", "positive_limit", "negative_limit", "sync_lost",
         "heartbeat_lost", "life_guard"]
"""


def _write(tmp_path: Path, text: str) -> Path:
    folder = tmp_path / "mini"
    folder.mkdir()
    path = folder / "profile.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_minimal_profile_loads(tmp_path: Path) -> None:
    data = servodesk_data.load_path(_write(tmp_path, MINIMAL))
    assert data.faults[0].name_zh is None  # optional
    # a user's profile may leave out the Chinese of the cause and the check
    assert (data.faults[0].description_zh, data.faults[0].what_to_check_zh) == (None, None)
    assert data.parameter("Window").object == (0x6065, 0)
    assert data.fault_for_kind(FaultKind.SYNC_LOST) == data.fault(0x1000)
    assert data.fault_for_kind(FaultKind.HOMING_ERROR) is None
    with pytest.raises(KeyError, match="no parameter 'PA-1'"):
        data.parameter("PA-1")


BAD = [  # (text to replace, replacement, expected message after the file name)
    ("vendor_id = 1\n", "", r"identity\.vendor_id: missing"),
    ('name = "mini"', 'name = "other"', r"identity\.name: 'other' must equal the profile fold"),
    ("rpdo_count = 4", 'rpdo_count = "4"', r"quirks\.rpdo_count: expected an integer"),
    ("rpdo_count = 4", "rpdo_count = true", r"quirks\.rpdo_count: expected an integer"),
    ("max = 500", "max = 500.0", r"\(Window\)\.max: expected an integer, got 500\.0"),
    ("sdo_block_transfer = false", "sdo_block_transfer = 0", r"sdo_block_transfer: expected true"),
    ('emcy_format = "cia301"', 'emcy_format = "x"', r"quirks\.emcy_format: 'x' is not one of"),
    ("rpdo_count = 4", "rpdo_count = 4\nemcy_fromat = 1", r"quirks: unknown key\(s\) emcy_fromat"),
    ('node_id_source = "fixed"', 'node_id_source = "parameter"', r"quirks\.node_id_object: requir"),
    ('"homing_error"]', '"homing"]', r"quirks\.status_only_kinds: 'homing' is not one of"),
    ('object = "6065:00"', 'object = "6065-00"', r"parameters\[0\] \(Window\)\.object: object"),
    ("default = 100", "default = 1000", r"\(Window\)\.default: 1000 is outside 0\.\.500"),
    ("default = 100", 'default = 100\nchoices = { 0 = "off" }', r"\(Window\)\.default: 100 is not"),
    ("default = 100", 'default = 100\nchoices = { 900 = "x" }', r"\(Window\)\.choices: code 900"),
    ('takes_effect = "immediately"', 'takes_effect = "later"', r"\(Window\)\.takes_effect: 'lat"),
    ("error_register = 0x01", "error_register = 0x02", r"faults\[0\] \(code 0x1000\)\.error_reg"),
    ("emcy_code = 0x1000", "emcy_code = 0x0010", r"\(code 0x1000\)\.emcy_code: 16 is outside"),
    ('"overspeed", ', "", r"faults: no fault for kind\(s\) overspeed"),
    ('"overspeed", ', '"overspeed", "overspeed", ', r"\(code 0x1000\)\.kinds: a kind is listed"),
    ('["homing_error"]', '["homing_error", "sync_lost"]', r"faults: sync_lost is also in quirks"),
    # a drive-inhibit drive stops at one switch: it has no single-switch fault, but one for both
    ('"fault"', '"inhibit"', r"faults: positive_limit is never raised with limit_switch_reac"),
    ('"fault"', '"stop"', r"quirks\.limit_switch_reaction: 'stop' is not one of 'fault', 'inh"),
    ('"life_guard"]', '"life_guard", "both_limits"]', r"both_limits is never raised with limit"),
    ("kinco_fault_bits = false", "kinco_fault_bits = true", r"\.kinco_bit: 0x0 is not a single"),
    ('seed = "none"', 'seed = "none', r"not valid TOML"),
    # name_zh is ServoDesk's Chinese for an English-only source: Chinese, and never beside the
    # manual's own Chinese name
    (
        'name_en = "Generic"',
        'name_en = "Generic"\nname_zh = "Generic"',
        r"\.name_zh: 'Generic' is n",
    ),
    (
        'name = "Generic"',
        'name = "通用"\nname_zh = "通用错误"',
        r"\.name_zh: the manual's name is Ch",
    ),
    # the Chinese of the cause and the check, when given, is Chinese
    (
        'what_to_check = "test"',
        'what_to_check = "test"\ndescription_zh = "test"',
        r"\.description_zh: 'test' is not",
    ),
    (
        'what_to_check = "test"',
        'what_to_check = "test"\nwhat_to_check_zh = ""',
        r"\.what_to_check_zh: expected a non-empty",
    ),
]


@pytest.mark.parametrize(("old", "new", "message"), BAD)
def test_loader_errors_name_file_and_key(tmp_path: Path, old: str, new: str, message: str) -> None:
    assert old in MINIMAL
    path = _write(tmp_path, MINIMAL.replace(old, new, 1))
    with pytest.raises(ValueError, match=message) as info:
        servodesk_data.load_path(path)
    assert str(info.value).startswith(str(path))


def test_inhibit_profile_maps_both_limits_instead_of_each_switch(tmp_path: Path) -> None:
    text = MINIMAL.replace('"fault"', '"inhibit"').replace(
        '"positive_limit", "negative_limit"', '"both_limits"'
    )
    data = servodesk_data.load_path(_write(tmp_path, text))
    assert data.fault_for_kind(FaultKind.BOTH_LIMITS) == data.fault(0x1000)
    assert data.fault_for_kind(FaultKind.POSITIVE_LIMIT) is None


def test_duplicate_fault_code_is_refused(tmp_path: Path) -> None:
    second = MINIMAL[MINIMAL.index("[[faults]]") :].replace('"overspeed", ', "")
    path = _write(tmp_path, MINIMAL.replace('"overspeed", ', "") + second.replace("sync_lost", "x"))
    with pytest.raises(ValueError, match=r"faults\[1\]"):
        servodesk_data.load_path(path)


def test_unknown_profile_is_refused() -> None:
    with pytest.raises(
        ValueError, match="unknown drive profile 'nope'; known: mdi-s1c, kinco, cia402"
    ):
        servodesk_data.load("nope")


def test_a_translated_fault_name_loads(tmp_path: Path) -> None:
    text = MINIMAL.replace('name_en = "Generic"', 'name_en = "Generic"\nname_zh = "通用错误"')
    assert servodesk_data.load_path(_write(tmp_path, text)).faults[0].name_zh == "通用错误"
