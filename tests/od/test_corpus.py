"""Every real vendor file loads, and each oddity SOURCES.md documents is reported, not hidden."""

from __future__ import annotations

from pathlib import Path

import pytest

from servodesk.od import DataType, ObjectDictionaryModel, load_od
from servodesk.od.lint import LintWarning
from tests.od.corpus import EDS_DIR, corpus, corpus_files

FILES = corpus_files()


def test_the_corpus_is_beside_the_checkout() -> None:
    """The vendor files live in ../shared/eds (CI has it beside the checkout); without them
    the tests below would prove nothing."""
    assert len(FILES) >= 20, f"expected the real EDS corpus in {EDS_DIR}, found {len(FILES)}"


def _matching(
    model: ObjectDictionaryModel, code: str, section: str | None, key: str | None
) -> list[LintWarning]:
    return [
        w
        for w in model.warnings
        if w.code == code
        and (section is None or w.section == section)
        and (key is None or w.key == key)
    ]


@pytest.mark.parametrize("path", FILES, ids=[p.name for p in FILES])
def test_every_corpus_file_loads_with_objects(path: Path) -> None:
    model = load_od(path)
    assert 0x1000 in model.objects  # Device type, mandatory in CiA 301
    assert all(obj.subs or obj.object_type in ("array", "record") for obj in model.objects.values())
    expected_format = {".eds": "eds", ".dcf": "dcf", ".xdd": "xdd", ".xpd": "xdd"}
    assert model.format == expected_format[path.suffix.lower()]
    for warning in model.warnings:
        assert warning.file == str(path)
        assert warning.message


def test_corpus_listing_matches_extensions_case_insensitively() -> None:
    names = {p.name for p in FILES}
    assert "Kinco_KINCO-JDFD.EDS" in names  # upper-case extension, missed by a "*.eds" glob
    assert {"CANopenNode_demoDevice.xdd", "CANopenNode_DS301_profile.xpd"} <= names


# One row per oddity named in SOURCES.md: file, code, section, key.
ODDITIES = [
    ("gbk_Kinco_KINCO-JDFD.eds", "encoding", None, None),
    ("CANopenNode_DS301_profile.eds", "empty-value", "DeviceInfo", "VendorNumber"),
    ("CANopenNode_DS301_profile.eds", "empty-value", "DeviceInfo", "ProductNumber"),
    ("Pilz-Schunk_prbt_0_1.dcf", "subnumber-mismatch", "20A0", "SubNumber"),
    ("Pilz-Schunk_prbt_0_1.dcf", "subnumber-mismatch", "2060", "SubNumber"),
    ("pythoncanopen_sample.eds", "subnumber-mismatch", "1018", "SubNumber"),
    ("pythoncanopen_sample.eds", "subnumber-mismatch", "1003", "SubNumber"),
    ("Elmo_elmo.dcf", "leading-zero", "FileInfo", "FileVersion"),
    ("Demaclenko_emecdrv5_rev09.eds", "byte-swapped", "1000", "DefaultValue"),
    ("Elmo_elmo.dcf", "inline-comment", "6502", "DefaultValue"),
    ("Ingenia_eve-net-c_1.8.1.eds", "float-literal", None, "DefaultValue"),
    ("CANopenNode_demoDevice.eds", "float-literal", "2120sub3", "DefaultValue"),
    ("ZeroErr_ZeroErr_Driver_V1.5.eds", "signed-hex", "607C", "LowLimit"),
    ("maxon_epos2_347717.eds", "signed-hex", None, None),
    ("Kinco_KINCO-JDFD.EDS", "array-without-datatype", None, None),
    ("pythoncanopen_example_e35.eds", "eds-version", "FileInfo", "EDSVersion"),
    ("ZeroErr_ZeroErr_Driver_V1.5.eds", "eds-version", "FileInfo", "EDSVersion"),
    ("Yiyou_YiyouServo_V1.4.eds", "line-endings", None, None),
    ("Yiyou_YiyouServo_V1.4.eds", "out-of-type-range", "2023", "HighLimit"),
    ("pythoncanopen_sample.eds", "nodeid-formula", "1403sub1", "DefaultValue"),
    ("ZeroErr_ZeroErr_Driver_V1.5.eds", "nodeid-case", None, None),
    ("Kinco_KINCO-JDFD.EDS", "access-case", None, "AccessType"),
    ("Kinco_KINCO-JDFD.EDS", "default-out-of-range", "2010sub0", "DefaultValue"),
    ("Kinco_KINCO-JDFD.EDS", "highest-subindex", "60F6sub0", "DefaultValue"),
    ("Elmo_elmo.dcf", "unknown-section", "PreDefines", None),
    ("ZeroErr_ZeroErr_Driver_V1.5.eds", "stray-subsection", "100Bsub0", None),
    ("pythoncanopen_sample.eds", "unknown-datatype", "2020", "DataType"),
    ("pythoncanopen_sample.eds", "no-subentries", "3003", None),
    ("pythoncanopen_example_e35.eds", "object-list", "OptionalObjects", None),
    ("pythoncanopen_example_e35.eds", "identity-mismatch", "1018sub1", "DefaultValue"),
    ("Sevcon_sevcon_gen4_simstub.eds", "unknown-key", "1018", "1_Sub0"),
    ("CANopenNode_DS301_profile.xpd", "disabled-object", "1002", None),
]


@pytest.mark.parametrize(
    ("name", "code", "section", "key"), ODDITIES, ids=[f"{r[0]}-{r[1]}" for r in ODDITIES]
)
def test_documented_oddity_is_reported(
    name: str, code: str, section: str | None, key: str | None
) -> None:
    model = load_od(corpus(name))
    assert _matching(model, code, section, key), [
        (w.code, w.section, w.key) for w in model.warnings
    ]


# Files that pass Lely's dcfchk (SOURCES.md table E): nothing worse than a note.
CLEAN = [
    "Faulhaber_605.3150.67-B-EK-2-60.eds",
    "Faulhaber_MCLM3002P-CO.eds",
    "maxon_motor_EPOS4_0170h_6150h_0000h_0000h.eds",
    "Yiyou_YiyouServo_V1.4.dcfgen.eds",
    "ros2canopen_cia402_slave.eds",
]


@pytest.mark.parametrize("name", CLEAN)
def test_files_that_pass_dcfchk_get_no_warnings(name: str) -> None:
    model = load_od(corpus(name))
    assert [w for w in model.warnings if w.severity != "info"] == []


def test_gbk_file_keeps_chinese_names_and_the_kinco_values() -> None:
    gbk = load_od(corpus("gbk_Kinco_KINCO-JDFD.eds"))
    original = load_od(corpus("Kinco_KINCO-JDFD.EDS"))
    assert gbk.encoding == "gbk"
    assert gbk.objects[0x1000].name == "设备类型 Device Type"
    assert gbk.objects[0x100C].name == "节点守护时间（单位：ms）"
    [encoding] = _matching(gbk, "encoding", None, None)
    assert "GBK" in encoding.message
    assert set(gbk.objects) == set(original.objects)
    assert gbk.get(0x2010, 0) == original.get(0x2010, 0)


def test_empty_vendor_number_is_unknown_not_fatal() -> None:
    model = load_od(corpus("CANopenNode_DS301_profile.eds"))
    assert model.device.vendor_number is None
    assert model.device.product_name == "New Product"
    assert len(model.objects) == 33


def test_subnumber_mismatch_keeps_the_sub_entries_present() -> None:
    model = load_od(corpus("pythoncanopen_sample.eds"))
    assert set(model.objects[0x1018].subs) == {0, 1, 2, 4}
    assert set(model.objects[0x1003].subs) == {0, 1, 3, 4, 5, 7}


def test_leading_zero_file_version_reads_as_decimal() -> None:
    assert load_od(corpus("Elmo_elmo.dcf")).device.file_version == 2


def test_byte_swapped_device_type_is_kept_as_written() -> None:
    model = load_od(corpus("Demaclenko_emecdrv5_rev09.eds"))
    assert model.get(0x1000, 0).default == 0x92020100  # type: ignore[union-attr]


def test_inline_comment_is_stripped_from_the_value() -> None:
    sub = load_od(corpus("Elmo_elmo.dcf")).get(0x6502, 0)
    assert sub is not None
    assert sub.default == 0x3ED
    assert sub.default_raw == "0x3ED"


def test_float_defaults_are_read_as_real32() -> None:
    sub = load_od(corpus("CANopenNode_demoDevice.eds")).get(0x2120, 3)
    assert sub is not None
    assert sub.data_type == DataType.REAL32
    assert sub.default == pytest.approx(12.345, rel=1e-7)


def test_raw_hex_signed_limit_is_twos_complement() -> None:
    sub = load_od(corpus("ZeroErr_ZeroErr_Driver_V1.5.eds")).get(0x607C, 0)  # Home offset
    assert sub is not None
    assert sub.data_type == DataType.INTEGER32
    assert sub.low == -(2**31)


def test_arrays_without_datatype_take_their_subs_types() -> None:
    model = load_od(corpus("Kinco_KINCO-JDFD.EDS"))
    arrays = [obj for obj in model.objects.values() if obj.object_type == "array"]
    assert len(arrays) == 8
    for obj in arrays:
        assert all(sub.data_type != DataType.DOMAIN for sub in obj.subs.values()), obj.name


def test_dcf_parameter_values_are_read_and_commented_ones_are_not() -> None:
    model = load_od(corpus("Elmo_elmo.dcf"), node_id=3)
    cob_id = model.get(0x1400, 1)  # RPDO1 COB-ID
    assert cob_id is not None
    assert (cob_id.value, cob_id.value_relative, cob_id.value_raw) == (0x203, True, "$NODEID+0x200")
    assert model.get(0x1600, 1).value == 0x60400010  # type: ignore[union-attr]
    assert model.get(0x1603, 2).value is None  # type: ignore[union-attr]  # ";ParameterValue=..."


def test_dcf_commissioning_node_id_resolves_relative_defaults() -> None:
    model = load_od(corpus("pythoncanopen_sample.eds"))  # [DeviceComissioning] NodeID=0x10
    assert model.node_id == 0x10
    assert model.get(0x1400, 1).default == 512 + 0x10  # type: ignore[union-attr]
    assert model.get(0x1403, 1).default == 1280 + 0x10  # type: ignore[union-attr]  # offset first


def test_compact_sub_obj_expands_with_names_from_the_name_section() -> None:
    obj = load_od(corpus("pythoncanopen_sample.eds")).objects[0x3004]
    assert obj.object_type == "array"
    assert sorted(obj.subs) == [0, 1, 2, 3]
    assert obj.subs[0].default == 3
    assert [obj.subs[i].name for i in (1, 2, 3)] == [f"Sensor Status {i}" for i in (1, 2, 3)]
    assert all(obj.subs[i].data_type == DataType.UNSIGNED16 for i in (1, 2, 3))


@pytest.mark.parametrize("node_id", [None, 4])
@pytest.mark.parametrize(
    ("eds", "xml"),
    [
        ("CANopenNode_demoDevice.eds", "CANopenNode_demoDevice.xdd"),
        ("CANopenNode_DS301_profile.eds", "CANopenNode_DS301_profile.xpd"),
    ],
)
def test_xdd_and_eds_of_one_device_give_the_same_dictionary(
    eds: str, xml: str, node_id: int | None
) -> None:
    from_eds = load_od(corpus(eds), node_id=node_id)
    from_xml = load_od(corpus(xml), node_id=node_id)
    assert from_xml.format == "xdd"
    assert set(from_eds.objects) == set(from_xml.objects)
    for index, obj in from_eds.objects.items():
        other = from_xml.objects[index]
        assert (obj.name, obj.object_type, set(obj.subs)) == (
            other.name,
            other.object_type,
            set(other.subs),
        )
        for subindex, sub in obj.subs.items():
            twin = other.subs[subindex]
            where = f"{index:04X}sub{subindex}"
            assert _empty_is_none(sub.default) == _empty_is_none(twin.default), where
            assert (sub.name, sub.access, sub.pdo_mappable, sub.relative) == (
                twin.name,
                twin.access,
                twin.pdo_mappable,
                twin.relative,
            ), where
            if sub.data_type != DataType.DOMAIN:  # CANopenEditor writes DOMAIN as BITSTRING
                assert sub.data_type == twin.data_type, where
    assert from_eds.device.vendor_number == from_xml.device.vendor_number
    assert from_eds.device.baud_rates == from_xml.device.baud_rates


def _empty_is_none(value: object) -> object:
    """An EDS writes `DefaultValue=` where an XDD leaves the default out."""
    return None if value in ("", b"") else value


def test_obj_flags_and_rww_access_are_kept() -> None:
    save = load_od(corpus("Faulhaber_605.3150.67-B-EK-2-60.eds")).get(0x1010, 4)  # Store params
    assert save is not None
    assert save.obj_flags == 3  # both CiA 306 tool hints set
    max_current = load_od(corpus("Demaclenko_emecdrv5_rev09.eds")).get(0x6073)  # Max current
    assert max_current is not None
    assert (max_current.access, max_current.pdo_mappable) == ("rww", True)
