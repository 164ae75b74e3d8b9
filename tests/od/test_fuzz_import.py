"""Property-based fuzzing of the tolerant EDS/DCF/XDD import with mutated real vendor files.

The entry point is the one the upload routes use: `servodesk.od.parser._parse` (run in a parse
worker process by `OdParser.parse`, which maps `OdImportError` to a 422) around `load_od_bytes`.
Property: a mutated file either gives a model whose warnings point at lines of the file, or the
documented "nothing usable" `OdImportError`; never any other exception.

Then hostile 20 MB files (one giant line, hundreds of thousands of bogus sections, deep XML
nesting, entity expansion): refused or read in bounded memory, with a generous hang guard.
"""

from __future__ import annotations

import re
import tracemalloc
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from servodesk.od import Code, ObjectDictionaryModel, OdImportError, load_od_bytes
from servodesk.od.parser import _assemble, _parse
from tests.od.corpus import corpus

# small and varied: a plain EDS, a DCF, a GBK-encoded EDS, CANopenNode's EDS and XDD
INI_FILES = (
    "ZLTech_zlac8015d_simulator.eds",
    "Pilz-Schunk_prbt_0_1.dcf",
    "gbk_Kinco_KINCO-JDFD.eds",
    "CANopenNode_demoDevice.eds",
    "Sevcon_sevcon_gen4_simstub.eds",
)
XML_FILES = ("CANopenNode_demoDevice.xdd", "CANopenNode_DS301_profile.xpd")
MB = 1024 * 1024

_CACHE: dict[str, bytes] = {}


def _read(name: str) -> bytes:
    if name not in _CACHE:
        path = corpus(name)
        if not path.is_file():  # CI has ../shared beside the checkout: a missing file fails
            pytest.fail(f"vendor file {path} is missing: ../shared/eds must sit beside the repo")
        _CACHE[name] = path.read_bytes()
    return _CACHE[name]


# ------------------------------------------------------------------------------ mutations

HOSTILE_VALUES = (
    b"",
    b"9" * 5000,  # beyond int()'s default digit limit
    b"0x" + b"F" * 400,
    b"-1",
    b"-0x80000000",
    b"-" * 3,
    b"0x",
    b"1e999",
    b"-1e999",
    b"nan",
    b"inf",
    b"0b102",
    b"1_000",
    b"\xff\xfe\x80\x81",  # not UTF-8
    b"\xc3",  # a cut UTF-8 sequence
    b"\x00\x01\x02",
    "²³".encode(),  # unicode digits: str.isdigit() but int() refuses them
    "٣".encode(),
    b"A" * 100_000,  # a very long line
    b"$NODEID",
    b"$NODEID+",
    b"+$NODEID",
    b"$NODEID*2",
    b"$NODEID+$NODEID",
    b"0x180+$NODEID+0x1",
    b"$NODEID+0xFFFFFFFFFFFFFFFFFF",
    b"$NODEID-0x1000",
    b"$NODEI",
    b"$nodeid+0x200",
    b"$NODEID+" + b"9" * 5000,
    b"0x180 ; comment",
    b";",
    b"=",
    b"[",
    b"]",
    b'"quoted"',
    b"0x7,0x8",
    b"   ",
)
HOSTILE_KEYS = (
    b"SubNumber",
    b"CompactSubObj",
    b"ObjectType",
    b"DataType",
    b"AccessType",
    b"DefaultValue",
    b"ParameterValue",
    b"LowLimit",
    b"HighLimit",
    b"PDOMapping",
    b"NodeID",
    b"SupportedObjects",
    b"1",
    b"99999",
    "²".encode(),
    b"9" * 5000,
    b"",
)
HOSTILE_SECTIONS = (
    b"[1000]",
    b"[1018sub9]",
    b"[1018subFFFFFFFF]",
    b"[1018sub]",
    b"[FFFFFFFF]",
    b"[10000]",
    b"[1600Name]",
    b"[1600Value]",
    b"[1003]\nCompactSubObj=254\nDataType=0x0007\nAccessType=ro\nParameterName=x",
    b"[1003]\nCompactSubObj=100000000\nObjectType=8",
    b"[1003Name]\nNrOfEntries=2\n\xc2\xb2=squared\n1=one",
    b"[MandatoryObjects]\nSupportedObjects=99999\n1=0x1000",
    b"[OptionalObjects]\nSupportedObjects=2\n1=0xZZ\n" + b"9" * 5000 + b"=0x1000",
    b"[DeviceInfo]\nVendorNumber=" + b"9" * 5000,
    b"[DeviceComissioning]\nNodeID=0x1000\nBaudrate=-1",
    b"[sub]",
    b"[]",
    b"[" + b"A" * 10_000,
)


def _lines(data: bytes) -> list[bytes]:
    return data.splitlines(keepends=True)


@st.composite
def _ini_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    kind = draw(
        st.sampled_from(
            (
                "flip",
                "insert",
                "delete",
                "truncate",
                "dup-line",
                "drop-line",
                "dup-section",
                "drop-section",
                "value",
                "key",
                "no-value",
                "section",
                "line-endings",
            )
        )
    )
    size = len(data)
    if kind == "flip":
        at = draw(st.integers(0, size - 1))
        return data[:at] + bytes([data[at] ^ draw(st.integers(1, 255))]) + data[at + 1 :]
    if kind == "insert":
        at = draw(st.integers(0, size))
        return data[:at] + draw(st.binary(min_size=1, max_size=16)) + data[at:]
    if kind == "delete":
        at = draw(st.integers(0, size - 1))
        return data[:at] + data[at + draw(st.integers(1, 4096)) :]
    if kind == "truncate":
        return data[: draw(st.integers(0, size))]
    if kind == "line-endings":
        return data.replace(b"\r\n", b"\r").replace(b"\n", b"\r")
    lines = _lines(data)
    if kind in ("dup-line", "drop-line"):
        if not lines:
            return data
        at = draw(st.integers(0, len(lines) - 1))
        lines[at : at + 1] = [lines[at]] * (2 if kind == "dup-line" else 0)
        return b"".join(lines)
    if kind in ("dup-section", "drop-section"):
        starts = [i for i, line in enumerate(lines) if line.lstrip().startswith(b"[")]
        if not starts:
            return data
        pick = draw(st.integers(0, len(starts) - 1))
        start = starts[pick]
        end = starts[pick + 1] if pick + 1 < len(starts) else len(lines)
        block = lines[start:end]
        if kind == "dup-section":
            lines[end:end] = block
        else:
            del lines[start:end]
        return b"".join(lines)
    keyed = [i for i, line in enumerate(lines) if b"=" in line]
    if not keyed:
        return data
    at = draw(st.sampled_from(keyed))
    key, _, rest = lines[at].partition(b"=")
    eol: bytes = rest[len(rest.rstrip(b"\r\n")) :] or b"\n"
    if kind == "value":
        lines[at] = key + b"=" + draw(st.sampled_from(HOSTILE_VALUES)) + eol
    elif kind == "key":
        value = draw(st.sampled_from(HOSTILE_VALUES))
        lines[at] = draw(st.sampled_from(HOSTILE_KEYS)) + b"=" + value + eol
    elif kind == "no-value":
        lines[at] = key + draw(st.sampled_from((b"=", b""))) + eol
    else:  # section: a hostile header or block in front of this line
        lines.insert(at, draw(st.sampled_from(HOSTILE_SECTIONS)) + b"\n")
    return b"".join(lines)


@st.composite
def ini_files(draw: st.DrawFn) -> tuple[str, bytes]:
    name = draw(st.sampled_from(INI_FILES))
    data = _read(name)
    for _ in range(draw(st.integers(1, 4))):
        if not data:
            break
        data = draw(_ini_mutation(data))
    return name, data


_ATTR = re.compile(rb'="[^"]*"')
_XML_VALUES = (
    b"",
    b"9" * 5000,
    b"0x" + b"F" * 400,
    b"-1",
    b"0x",
    b"garbage",
    b"$NODEID+",
    b"$NODEID+0x180",
    b"\xff\xfe",  # not UTF-8: expat refuses it
    b"&amp;&lt;",
    b"&undefined;",
    "²".encode(),
    b"A" * 100_000,
)
_XML_INSERTS = (
    b'<!DOCTYPE x [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;">]>',
    b'<!DOCTYPE x [<!ENTITY e SYSTEM "file:///etc/passwd">]>',
    b'<!DOCTYPE x [<!ENTITY % p SYSTEM "http://127.0.0.1:1/x.dtd"> %p;]>',
    b'<!DOCTYPE x SYSTEM "http://127.0.0.1:1/x.dtd">',
    b"<a>" * 5000 + b"</a>" * 5000,
    b"<CANopenObject/>",
    b'<CANopenObject index="1000" objectType="7"/>',
    b'<CANopenObject index="ZZZZ" subNumber="-1" objectType="99"/>',
    b'<CANopenObject index="2000" objectType="9" subNumber="2">'
    b'<CANopenSubObject subIndex="" dataType="ZZ"/><CANopenSubObject subIndex="1FF"/>'
    b"</CANopenObject>",
    b'<parameter uniqueID="dup"/><parameter uniqueID="dup"/>',
    b"<![CDATA[" + b"x" * 1000 + b"]]>",
    b"&amp;",
    b"<?pi data?>",
    b"</unbalanced>",
)


@st.composite
def _xml_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    kind = draw(st.sampled_from(("flip", "truncate", "attr", "insert", "prolog", "delete")))
    size = len(data)
    if kind == "flip":
        at = draw(st.integers(0, size - 1))
        return data[:at] + bytes([data[at] ^ draw(st.integers(1, 255))]) + data[at + 1 :]
    if kind == "truncate":
        return data[: draw(st.integers(0, size))]
    if kind == "delete":
        at = draw(st.integers(0, size - 1))
        return data[:at] + data[at + draw(st.integers(1, 256)) :]
    if kind == "prolog":  # a DOCTYPE after the XML declaration, before the root
        found = re.search(rb"<[A-Za-z]", data)
        root = found.start() if found else 0
        doctype: bytes = draw(st.sampled_from(_XML_INSERTS[:4]))
        return data[:root] + doctype + b"\n" + data[root:]
    if kind == "attr":
        spans = [m.span() for m in _ATTR.finditer(data)]
        if not spans:
            return data
        start, end = draw(st.sampled_from(spans))
        value: bytes = draw(st.sampled_from(_XML_VALUES))
        return data[:start] + b'="' + value + b'"' + data[end:]
    # insert: after the end of some start tag
    ends = [m.end() for m in re.finditer(rb"<[A-Za-z][^>]*[^/]>", data[:200_000])]
    if not ends:
        return data
    at = draw(st.sampled_from(ends))
    return data[:at] + draw(st.sampled_from(_XML_INSERTS)) + data[at:]


@st.composite
def xml_files(draw: st.DrawFn) -> tuple[str, bytes]:
    name = draw(st.sampled_from(XML_FILES))
    data = _read(name)
    for _ in range(draw(st.integers(1, 3))):
        if not data:
            break
        data = draw(_xml_mutation(data))
    return name, data


# ------------------------------------------------------------------------------ the property

# warnings about a line of the file: they must say which line
_LINE_CODES = frozenset(
    {
        Code.BAD_LINE,
        Code.OUTSIDE_SECTION,
        Code.DUPLICATE_SECTION,
        Code.DUPLICATE_KEY,
        Code.EMPTY_VALUE,
        Code.BAD_INTEGER,
        Code.BAD_FLOAT,
        Code.BAD_BYTES,
        Code.LEADING_ZERO,
        Code.INLINE_COMMENT,
        Code.NODEID_FORMULA,
        Code.BAD_ACCESS,
        Code.BAD_OBJECT_TYPE,
        Code.UNKNOWN_DATATYPE,
    }
)


def _import(name: str, data: bytes, node_id: int | None) -> ObjectDictionaryModel | None:
    """What the upload route does (minus the worker process); None for the documented refusal."""
    try:
        blob, chunks = _parse(data, name, node_id)
    except OdImportError as error:
        refusal = str(error)
    else:
        refusal = ""
    if refusal:
        assert name in refusal  # names the file (and the line, where there is one)
        return None
    model = _assemble(blob, chunks)
    # the line count the way the INI reader counts (\r\n, \r or \n), plus a final partial line
    lines = len(re.split(rb"\r\n|\r|\n", data))
    assert model.objects
    for warning in model.warnings:
        assert warning.file == name
        assert warning.message
        assert warning.severity in ("info", "warning", "error")
        if warning.line is not None:
            assert 1 <= warning.line <= lines, warning
        if warning.code in _LINE_CODES:
            assert warning.line is not None, warning
    for index, obj in model.objects.items():
        assert 0 <= index <= 0xFFFF
        for subindex, sub in obj.subs.items():
            assert 0 <= subindex <= 0xFF
            assert (sub.index, sub.subindex) == (index, subindex)
    return model


def _or_empty(name: str) -> bytes:
    """A corpus file for an @example (empty when the corpus is absent: the tests skip then)."""
    path = corpus(name)
    return path.read_bytes() if path.is_file() else b""


_EDS = _or_empty(INI_FILES[0])
_XDD = _or_empty(XML_FILES[0])
_COMPACT = (
    b"\n[1003]\nParameterName=E\nObjectType=0x8\nDataType=0x7\nAccessType=ro\nCompactSubObj=2\n"
)


def _attr(name: bytes, value: bytes) -> bytes:
    """The XDD with the first `name="..."` attribute set to `value`."""
    return re.sub(rb' %s="[^"]*"' % name, b' %s="%s"' % (name, value), _XDD, count=1)


FUZZ = settings(
    max_examples=250,
    derandomize=True,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


@FUZZ
@given(ini_files(), st.sampled_from((None, 1, 127)))
# regressions: [xxxxName] keys "²" (str.isdigit(), int() refuses) and 5000 digits (int() limit)
@example(("x.eds", _EDS + _COMPACT + "[1003Name]\n\u00b2=squared\n".encode()), None)
@example(("x.eds", _EDS + _COMPACT + b"[1003Name]\n" + b"9" * 5000 + b"=x\n"), None)
def test_mutated_eds_and_dcf_files_import_or_are_refused(
    file: tuple[str, bytes], node_id: int | None
) -> None:
    _import(*file, node_id)


@settings(FUZZ, max_examples=120)
@given(xml_files(), st.sampled_from((None, 5)))
# regressions: encodings expat cannot use raised LookupError / ValueError
@example(("x.xdd", _XDD.replace(b'encoding="utf-8"', b'encoding="xtf-8"', 1)), None)
@example(("x.xdd", _XDD.replace(b'encoding="utf-8"', b'encoding="gbk"', 1)), None)
# index / subIndex beyond 16 / 8 bits, or negative, were taken by int(x, 16)
@example(("x.xdd", _attr(b"index", b"10000")), None)
@example(("x.xdd", _attr(b"index", b"-1")), None)
@example(("x.xdd", _attr(b"subIndex", b"1FF")), None)
# "²" and 5000 digits in decimal attributes: str.isdigit() then int() raised ValueError
@example(("x.xdd", _attr(b"objectType", b"9" * 5000)), None)
@example(("x.xdd", _attr(b"subNumber", "\u00b2".encode())), None)
@example(("x.xdd", _attr(b"granularity", "\u00b2".encode())), None)
@example(("x.xdd", _attr(b"entry", b"Dummy\xc2\xb2=1")), None)
def test_mutated_xdd_files_import_or_are_refused(
    file: tuple[str, bytes], node_id: int | None
) -> None:
    _import(*file, node_id)


def test_unmutated_corpus_files_still_import() -> None:
    for name in INI_FILES + XML_FILES:
        assert _import(name, _read(name), None) is not None


# ------------------------------------------------------------------------------ XML safety


def _xdd_with_doctype(doctype: bytes, body: bytes = b"") -> bytes:
    data = _read(XML_FILES[0])
    found = re.search(rb"<[A-Za-z]", data)
    assert found is not None
    root = found.start()
    close = data.index(b">", root) + 1
    return data[:root] + doctype + b"\n" + data[root:close] + body + data[close:]


@pytest.mark.parametrize(
    "doctype",
    [
        b'<!DOCTYPE x [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]>',
        b'<!DOCTYPE x [<!ENTITY e SYSTEM "file:///etc/passwd">]>',
        b'<!DOCTYPE x [<!ENTITY % p SYSTEM "file:///etc/passwd"> %p;]>',
    ],
)
def test_xml_entities_are_refused(doctype: bytes) -> None:
    with pytest.raises(OdImportError, match="entities"):
        load_od_bytes(_xdd_with_doctype(doctype, b"&e;" if b"passwd" in doctype else b""), "x.xdd")


def test_an_external_dtd_is_not_fetched(tmp_path: Path) -> None:
    secret = tmp_path / "secret.dtd"
    secret.write_text('<!ENTITY leak "LEAKED">', encoding="utf-8")
    data = _xdd_with_doctype(f'<!DOCTYPE x SYSTEM "{secret.as_uri()}">'.encode(), b"")
    model = load_od_bytes(data, "x.xdd")
    assert all("LEAKED" not in (w.message or "") for w in model.warnings)


# ------------------------------------------------------------------------------ 20 MB hostile files


def _peak_of(name: str, data: bytes) -> tuple[int, ObjectDictionaryModel | None]:
    """Peak Python heap above the start while importing (the file itself excluded)."""
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        try:
            model: ObjectDictionaryModel | None = load_od_bytes(data, name)
        except OdImportError:
            model = None
        peak = tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()
    return peak, model


def _giant_line_eds() -> bytes:
    head = _read("ZLTech_zlac8015d_simulator.eds")
    return head + b"\n[2000]\nParameterName=" + b"A" * (20 * MB) + b"\nDataType=0x7\n"


def _bogus_sections_eds() -> bytes:
    head = _read("ZLTech_zlac8015d_simulator.eds")
    bogus = b"".join(b"[%Xsub%X]\nX=\n" % (0x2000 + n // 200, n % 200) for n in range(1_450_000))
    return head + b"\n" + bogus


def _bogus_lines_eds() -> bytes:
    head = _read("ZLTech_zlac8015d_simulator.eds")
    return head + b"\n[2000]\n" + b"not a key value line\n" * (20 * MB // 21)


def _deep_xdd() -> bytes:
    depth = 20 * MB // 7  # <a> and </a>: 7 bytes a level
    return _xdd_with_doctype(b"", b"<a>" * depth + b"</a>" * depth)


def _many_elements_xdd() -> bytes:
    return _xdd_with_doctype(b"", b"<a/>" * (20 * MB // 4))


def _laughs_xdd() -> bytes:
    entities = [b'<!ENTITY l0 "lol">'] + [
        b'<!ENTITY l%d "%s">' % (n, b"&l%d;" % (n - 1) * 10) for n in range(1, 10)
    ]
    doctype = b"<!DOCTYPE x [" + b"".join(entities) + b"]>"
    return _xdd_with_doctype(doctype, b"&l9;" * (20 * MB // 4))


@pytest.mark.timeout(120)
@pytest.mark.parametrize(
    ("name", "make"),
    [
        ("giant-line.eds", _giant_line_eds),
        ("bogus-sections.eds", _bogus_sections_eds),
        ("bogus-lines.eds", _bogus_lines_eds),
        ("deep.xdd", _deep_xdd),
        ("many-elements.xdd", _many_elements_xdd),
        ("laughs.xdd", _laughs_xdd),
    ],
)
def test_hostile_20_mb_files_import_in_bounded_memory(name: str, make: object) -> None:
    assert callable(make)
    data: bytes = make()
    assert len(data) >= 10 * MB
    peak, model = _peak_of(name, data)
    assert peak < 10 * len(data), f"{name}: peak {peak / MB:.0f} MB for {len(data) / MB:.0f} MB"
    if model is not None:
        assert model.warnings  # the hostile part is reported, not silently taken
