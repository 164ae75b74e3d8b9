"""EDS/DCF import on small hand-written files: each repair is reported at its line."""

from __future__ import annotations

import pytest

from servodesk.od import DataType, ObjectDictionaryModel, OdImportError, lint_report, load_od_bytes

HEAD = """[FileInfo]
FileName=t.eds
EDSVersion=4.0

[DeviceInfo]
VendorName=ServoDesk test
VendorNumber=0x9A
ProductNumber=0x1
RevisionNumber=0x2
BaudRate_250=1
BaudRate_500=1
NrOfRXPDO=1
NrOfTXPDO=1

[DummyUsage]
Dummy0005=1

[MandatoryObjects]
SupportedObjects=3
1=0x1000
2=0x1001
3=0x1018

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00020192
PDOMapping=0

[1001]
ParameterName=Error register
ObjectType=0x7
DataType=0x0005
AccessType=ro
PDOMapping=1

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=2

[1018sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=const
DefaultValue=1
PDOMapping=0

[1018sub1]
ParameterName=Vendor-ID
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x9A
PDOMapping=0
"""


def _load(
    extra: str = "", *, name: str = "t.eds", node_id: int | None = None
) -> ObjectDictionaryModel:
    return load_od_bytes((HEAD + extra).encode(), name, node_id=node_id)


def _codes(model: ObjectDictionaryModel) -> list[str]:
    return [w.code for w in model.warnings]


def _var(index: str, lines: str) -> str:
    return f"\n[OptionalObjects]\nSupportedObjects=1\n1=0x{index}\n\n[{index}]\n{lines}\n"


def test_a_clean_file_gives_no_warnings() -> None:
    model = _load()
    assert model.warnings == ()
    assert model.format == "eds"
    assert sorted(model.objects) == [0x1000, 0x1001, 0x1018]
    assert model.device.vendor_number == 0x9A
    assert model.device.baud_rates == frozenset({250_000, 500_000})
    assert model.device.dummy_usage == frozenset({5})
    assert model.get(0x1018, 1).default == 0x9A  # type: ignore[union-attr]


@pytest.mark.parametrize(
    ("data", "name"),
    [
        (b"", "t.eds"),
        (b"just some text\nwithout sections\n", "t.eds"),
        (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "t.eds"),
        (b"[FileInfo]\nFileName=x\n[DeviceInfo]\nVendorName=x\n", "t.dcf"),
        (b"<?xml version='1.0'?><ISO15745ProfileContainer/>", "t.xdd"),
        (b"<broken", "t.xdd"),
    ],
    ids=["empty", "plain-text", "binary", "no-objects", "xml-no-objects", "bad-xml"],
)
def test_nothing_usable_raises(data: bytes, name: str) -> None:
    with pytest.raises(OdImportError):
        load_od_bytes(data, name)


def test_format_follows_the_extension_case_insensitively() -> None:
    assert _load(name="DRIVE.EDS").format == "eds"
    assert _load(name="Drive.DCF").format == "dcf"
    commissioning = "\n[DeviceComissioning]\nNodeID=3\n"
    assert _load(commissioning, name="upload.bin").format == "dcf"


@pytest.mark.parametrize(
    ("lines", "code", "key", "check"),
    [
        (
            "ParameterName=X\nDataType=0x0006\nPDOMapping=0",
            "bad-access",
            "AccessType",
            lambda m: m.get(0x2000).access == "ro",
        ),
        (
            "ParameterName=X\nDataType=0x0006\nAccessType=rwx",
            "bad-access",
            "AccessType",
            lambda m: m.get(0x2000).access == "ro",
        ),
        (
            "ParameterName=X\nAccessType=rw",
            "missing-datatype",
            "DataType",
            lambda m: m.get(0x2000).data_type == DataType.DOMAIN,
        ),
        (
            "DataType=0x0006\nAccessType=rw",
            "missing-name",
            None,
            lambda m: m.objects[0x2000].name == "Object 2000h",
        ),
        (
            "ParameterName=X\nObjectType=0x10\nDataType=0x0006\nAccessType=rw",
            "bad-object-type",
            "ObjectType",
            lambda m: m.objects[0x2000].object_type == "var",
        ),
        (
            "ParameterName=X\nDataType=0x0006\nAccessType=rw\nDefaultValue=",
            "empty-value",
            "DefaultValue",
            lambda m: m.get(0x2000).default is None,
        ),
        (
            "ParameterName=X\nDataType=0x0006\nAccessType=rw\nDefaultValue=9\nLowLimit=1\nHighLimit=5",
            "default-out-of-range",
            "DefaultValue",
            lambda m: m.get(0x2000).default == 9,
        ),
        (
            "ParameterName=X\nDataType=0x0006\nAccessType=rw\nLowLimit=5\nHighLimit=1",
            "limits-inverted",
            "LowLimit",
            lambda m: (m.get(0x2000).low, m.get(0x2000).high) == (5, 1),
        ),
        (
            "ParameterName=X\nDataType=0x0006\nAccessType=rw\nDefaultValue=0x2A ; answer",
            "inline-comment",
            "DefaultValue",
            lambda m: m.get(0x2000).default == 42,
        ),
        (
            "ParameterName=X\nDataType=0x0006\nAccessType=rw\nDefaultValue=010",
            "leading-zero",
            "DefaultValue",
            lambda m: m.get(0x2000).default == 10,
        ),
        (
            "ParameterName=X\nDataType=0x0006\nAccessType=rw\nMaxSpeed=3",
            "unknown-key",
            "MaxSpeed",
            lambda m: m.get(0x2000).name == "X",
        ),
        (
            "ParameterName=X\nDataType=0x0040\nAccessType=rw\nDefaultValue=0x0",
            "unknown-datatype",
            "DataType",
            lambda m: m.get(0x2000).default == b"\x00",
        ),
    ],
    ids=lambda v: v if isinstance(v, str) and "\n" not in v and "=" not in v else None,
)
def test_entry_repairs_are_reported_at_their_key(
    lines: str, code: str, key: str | None, check: object
) -> None:
    model = _load(_var("2000", lines))
    matching = [w for w in model.warnings if w.code == code]
    assert matching, _codes(model)
    assert matching[0].section == "2000"
    assert matching[0].key == key
    assert matching[0].line is not None
    assert callable(check)
    assert check(model)


def test_upper_case_access_types_give_one_note_for_the_file() -> None:
    extra = _var("2000", "ParameterName=A\nDataType=0x0005\nAccessType=RW") + (
        "\n[2001]\nParameterName=B\nDataType=0x0005\nAccessType=RO\n"
    )
    model = _load(extra)
    [note] = [w for w in model.warnings if w.code == "access-case"]
    assert note.severity == "info"
    assert "2 entries" in note.message
    assert (model.get(0x2000).access, model.get(0x2001).access) == ("rw", "ro")  # type: ignore[union-attr]


def test_sub_sections_without_their_object_are_an_error() -> None:
    model = _load("\n[2000sub1]\nParameterName=X\nDataType=0x0005\nAccessType=rw\n")
    [error] = [w for w in model.warnings if w.severity == "error"]
    assert (error.code, error.section) == ("stray-subsection", "2000sub1")
    assert 0x2000 not in model.objects


def test_subnumber_and_highest_subindex_are_checked() -> None:
    extra = _var(
        "2000",
        "ParameterName=Table\nObjectType=0x8\nSubNumber=5\n\n[2000sub0]\nParameterName=N\n"
        "DataType=0x0005\nAccessType=ro\nDefaultValue=4\n\n[2000sub1]\nParameterName=E1\n"
        "DataType=0x0006\nAccessType=rw\n",
    )
    model = _load(extra)
    assert "subnumber-mismatch" in _codes(model)
    assert "highest-subindex" in _codes(model)
    assert model.objects[0x2000].object_type == "array"
    assert model.get(0x2000, 1).data_type == DataType.UNSIGNED16  # type: ignore[union-attr]


def test_compact_array_takes_dcf_values_from_the_value_section() -> None:
    extra = _var(
        "2000",
        "ParameterName=Gains\nObjectType=0x8\nCompactSubObj=2\nDataType=0x0003\nAccessType=rw\n"
        "DefaultValue=0\nPDOMapping=1\n\n[2000Value]\nNrOfEntries=2\n1=-7\n2=0x10\n",
    )
    obj = _load(extra).objects[0x2000]
    assert [(s.subindex, s.name, s.value) for s in obj.subs.values()] == [
        (0, "NrOfObjects", None),
        (1, "Gains1", -7),
        (2, "Gains2", 0x10),
    ]
    assert obj.subs[0].default == 2


def test_dcf_node_id_resolves_relative_values_unless_one_is_given() -> None:
    extra = _var(
        "1014",
        "ParameterName=COB-ID EMCY\nDataType=0x0007\nAccessType=ro\n"
        "DefaultValue=$NODEID+0x80\nParameterValue=$NODEID+0x80",
    )
    extra += "\n[DeviceComissioning]\nNodeID=0x21\nBaudrate=500\n"
    from_file = _load(extra, name="t.dcf")
    assert from_file.node_id == 0x21
    assert from_file.device.baud_rate == 500_000
    assert (from_file.get(0x1014).default, from_file.get(0x1014).value) == (0xA1, 0xA1)  # type: ignore[union-attr]
    given = _load(extra, name="t.dcf", node_id=3)
    assert given.get(0x1014).default == 0x83  # type: ignore[union-attr]


@pytest.mark.parametrize(
    ("device_type", "warned"),
    [
        ("0x00020192", False),
        ("0xFFFF0192", False),  # ros2_canopen's fake slave: additional info bits set
        ("0x00000000", False),
        ("0x0000FFFF", False),  # manufacturer-specific, not a swapped profile
        ("0x92020100", True),  # Demaclenko (SOURCES.md)
        ("0x92010000", True),  # 0x00000192 byte-reversed
    ],
)
def test_byte_swapped_device_type(device_type: str, warned: bool) -> None:
    text = HEAD.replace("DefaultValue=0x00020192", f"DefaultValue={device_type}")
    model = load_od_bytes(text.encode(), "t.eds")
    assert ("byte-swapped" in _codes(model)) is warned


def test_identity_mismatch_between_device_info_and_1018() -> None:
    model = load_od_bytes(HEAD.replace("VendorNumber=0x9A", "VendorNumber=0x9B").encode(), "t.eds")
    [warning] = [w for w in model.warnings if w.code == "identity-mismatch"]
    assert (warning.section, "0x9B" in warning.message) == ("1018sub1", True)


@pytest.mark.parametrize(
    ("mapping", "problem"),
    [
        ("0x10010008", None),  # Error register, 8 bits, mappable
        ("0x00050008", None),  # dummy UNSIGNED8
        ("0x10010010", "maps 16 bits"),
        ("0x60410010", "not in the object dictionary"),
        ("0x10000020", "not marked PDO-mappable"),
    ],
)
def test_default_pdo_mapping_is_checked(mapping: str, problem: str | None) -> None:
    extra = _var(
        "1A00",
        "ParameterName=TPDO1 mapping\nObjectType=0x9\n\n[1A00sub0]\nParameterName=N\n"
        "DataType=0x0005\nAccessType=rw\nDefaultValue=1\n\n[1A00sub1]\nParameterName=M1\n"
        f"DataType=0x0007\nAccessType=rw\nDefaultValue={mapping}\n",
    )
    messages = [w.message for w in _load(extra).warnings if w.code == "pdo-mapping"]
    if problem is None:
        assert messages == []
    else:
        assert len(messages) == 1
        assert problem in messages[0]


def test_eds_version_and_object_lists() -> None:
    text = HEAD.replace("EDSVersion=4.0", "EDSVersion=402").replace(
        "3=0x1018", "3=0x1018\n4=0x1002"
    )
    codes = _codes(load_od_bytes(text.encode(), "t.eds"))
    assert codes.count("eds-version") == 1
    assert codes.count("object-list") == 2  # 1002h missing, and 4 listed for SupportedObjects=3


def test_xml_inside_an_eds_is_read_as_xdd() -> None:
    xml = b"""<?xml version="1.0"?><ISO15745ProfileContainer><ISO15745Profile><ProfileBody>
    <ApplicationLayers><CANopenObjectList>
    <CANopenObject index="1000" name="Device type" objectType="7" dataType="0007" accessType="ro"
      defaultValue="0x00020192"/>
    </CANopenObjectList></ApplicationLayers></ProfileBody></ISO15745Profile>
    </ISO15745ProfileContainer>"""
    model = load_od_bytes(xml, "odd.eds")
    assert model.format == "xdd"
    assert model.get(0x1000).default == 0x20192  # type: ignore[union-attr]
    assert "xml" in _codes(model)


def test_lint_report_has_one_line_per_warning_in_file_order() -> None:
    model = _load(_var("2000", "ParameterName=X\nDataType=0x0006\nAccessType=rw\nDefaultValue=0x"))
    report = lint_report(model).splitlines()
    assert len(report) == len(model.warnings) == 1
    line = model.warnings[0].line
    assert report[0] == (
        f"t.eds:{line} [2000] DefaultValue: DefaultValue '0x' is not a number; left empty "
        "(warning bad-integer)"
    )


def test_utf16_file_from_a_windows_editor_loads() -> None:
    model = load_od_bytes(HEAD.encode("utf-16"), "t.eds")
    assert sorted(model.objects) == [0x1000, 0x1001, 0x1018]
    assert [w.code for w in model.warnings] == ["encoding"]
