"""EMCY frames in words, layered: the drive's own alarm table first (MDi-S1-C CANopen manual
§4.1 alarm numbers, Kinco servo CANopen manual §8 603Fh codes), then CiA 402, then CiA 301,
then the code's class with its raw hex: never nothing.

Chinese names: an MDi-S1-C alarm keeps its manual's own Chinese name ("manual"); the Kinco
manual and the CiA 301/402 tables are English only, so their Chinese is ServoDesk's translation
("translation": the profile's name_zh, servodesk_protocol.emcy_codes' `_ZH` tables), the English
kept as the source has it.

`check` and `check_zh` say the same parts in the same order ("Cause: …" / "原因：…", "Check:" /
"检查：", "CiA class:" / "CiA 类别：", "CiA code 8611h:" / "CiA 代码 8611h：", "Error register
21h:" / "错误寄存器 21h：", "Source:" / "来源："), one space between parts; `check_zh` is None when
`check` is, or when a part has no Chinese (a user's profile without description_zh /
what_to_check_zh): never half English.

Pure: `decode_emcy(profile, node, data)` takes the node's profile data (None when its identity
is unknown: the CiA 301 format is assumed) and an EMCY's data bytes; the caller supplies the time.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

from servodesk.faults.cia301 import cia_text
from servodesk_data import DriveData, EmcyFormat, FaultEntry
from servodesk_protocol import emcy_codes
from servodesk_protocol.emcy import FRAME_LENGTH
from servodesk_protocol.emcy_codes import CodeSource, is_reset

# where each shipped profile's fault table comes from, by profile name
_MANUALS = {
    "mdi-s1c": "MDi-S1-C CANopen manual §4.1",
    "kinco": "Kinco servo CANopen manual §8",
    "cia402": "Nanotec CANopen article",
}
# the same in Chinese, as the page names the manuals
_MANUALS_ZH = {
    "mdi-s1c": "MDi-S1-C CANopen 手册 §4.1",
    "kinco": "步科伺服 CANopen 手册 §8",
    "cia402": "Nanotec CANopen 文章",
}
_ALARM = EmcyFormat.ALARM_NUMBER
# where a record's name_zh comes from (the API's `name_zh_source`)
ZH_MANUAL = "manual"  # the drive manual's own Chinese (MDi-S1-C)
ZH_TRANSLATION = "translation"  # ServoDesk's translation of an English source
# entries a shipped table holds for the simulated drive although the manual has no such code:
# (profile, code) -> what the manual says instead
_NOT_IN_MANUAL = {
    ("kinco", 0x8400): "the Kinco servo CANopen manual §8 marks 2600h:02 bit 4000h"
    " (FAULT_OVERSPEEDERROR_BIT) not used, 603Fh code 0: a real drive does not send it",
}
_NOT_IN_MANUAL_ZH = {
    ("kinco", 0x8400): "步科伺服 CANopen 手册 §8 标注 2600h:02 位 4000h"
    "（FAULT_OVERSPEEDERROR_BIT）未使用，603Fh 代码为 0：实际驱动器不会发送此故障",
}
_END_ZH = "。！？；"  # a Chinese part ends with one of these, else gets 。


@dataclass(frozen=True, slots=True)
class FaultRecord:
    """One decoded fault; the fields are the API's `Fault`."""

    time: float
    node: int
    code: int  # the format's own code: MDi alarm number, low 16 bits of Kinco 603Fh, EMCY code
    code_hex: str  # "0x8611"
    source: str  # CodeSource value: vendor | cia402 | cia301 | unknown
    name_en: str
    name_zh: str | None
    name_zh_source: str | None  # ZH_MANUAL | ZH_TRANSLATION; None when name_zh is None
    check: str | None  # cause and what to check, when a table says
    error_register: int | None  # only the CiA 301 format carries 1001h
    manufacturer_hex: str | None  # CiA 301 bytes 3–7, raw
    raw_hex: str  # the whole EMCY data
    # `check` in Chinese, part for part; None when check is None or a part has no Chinese
    check_zh: str | None = None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def fault_words(record: FaultRecord, profile: DriveData | None) -> str:
    """One phrase for a timeline: "alarm 4 位置超差 Following error" for an MDi alarm number,
    "0x8611 Following error" for an EMCY code (the timeline keeps the source's words: a
    translated name stays out)."""
    manual = record.name_zh and record.name_zh_source == ZH_MANUAL
    name = f"{record.name_zh} {record.name_en}" if manual else record.name_en
    if profile is not None and profile.quirks.emcy_format is EmcyFormat.ALARM_NUMBER:
        return f"alarm {record.code} {name}"
    return f"{record.code_hex} {name}"


@dataclass(frozen=True, slots=True)
class _Raw:
    """What the frame itself carries, beside the code."""

    raw_hex: str
    error_register: int | None
    manufacturer_hex: str | None


def decode_emcy(
    profile: DriveData | None, node: int, data: bytes, *, time: float = 0.0
) -> FaultRecord:
    """The EMCY `data` of `node` in words (see the module docstring for the layering)."""
    fmt = profile.quirks.emcy_format if profile is not None else EmcyFormat.CIA301
    raw_hex = data.hex(" ").upper()
    if len(data) < 2:
        text = f"Malformed EMCY ({len(data)} data bytes, the code needs 2)"
        text_zh = _translated(f"EMCY 格式错误（{len(data)} 个数据字节，错误代码需要 2 个）")
        raw = _Raw(raw_hex, None, None)
        return _record(time, node, 0, CodeSource.UNKNOWN, text, raw, name_zh=text_zh)
    code = int.from_bytes(data[:2], "little")
    register: int | None = None
    manufacturer: str | None = None
    if fmt is EmcyFormat.CIA301 and len(data) >= 3:  # a 2-byte frame: an alarm-number drive
        register = data[2]
        manufacturer = data[3:FRAME_LENGTH].hex(" ").upper()
    raw = _Raw(raw_hex, register, manufacturer)
    if is_reset(code) and (fmt is EmcyFormat.CIA301 or code == 0):
        # an alarm-number drive's alarm 0 keeps its words as before (no Chinese)
        reset_zh = None if fmt is _ALARM else _translated(emcy_codes.RESET_TEXT_ZH)
        reset = emcy_codes.RESET_TEXT
        return _record(time, node, code, CodeSource.CIA301, reset, raw, name_zh=reset_zh)
    if profile is not None and fmt is EmcyFormat.ALARM_NUMBER:
        entry = profile.fault(code)
        if entry is None:
            manual = _MANUALS.get(profile.profile, "drive's alarm table")
            text = f"Unknown alarm {code} (not in the {manual})"
            manual_zh = _MANUALS_ZH.get(profile.profile, "驱动器报警表")
            gap = " " if manual_zh[-1].isascii() else ""
            text_zh = _translated(f"未知报警 {code}（{manual_zh}{gap}中没有）")
            return _record(time, node, code, CodeSource.UNKNOWN, text, raw, name_zh=text_zh)
        return _vendor(time, node, code, [entry], profile, raw)
    if profile is not None:
        entries = _matching(profile, code, fmt)
        if entries:
            return _vendor(time, node, code, entries, profile, raw)
    # every shipped profile is a drive, and an unknown node of a servo tool most likely one
    cia = cia_text(code, cia402=True)
    parts = [] if cia.source is CodeSource.UNKNOWN else [f"CiA class: {cia.code_class}."]
    parts_zh = (
        []
        if cia.source is CodeSource.UNKNOWN
        else [f"CiA 类别：{emcy_codes.code_class_zh(code)}。"]
    )
    if register:
        words = ", ".join(emcy_codes.error_register_words(register))
        parts.append(f"Error register {register:02X}h: {words}.")
        words_zh = "、".join(emcy_codes.error_register_words_zh(register))
        parts_zh.append(f"错误寄存器 {register:02X}h：{words_zh}。")
    check = " ".join(parts) or None
    check_zh = " ".join(parts_zh) if check is not None else None
    cia_zh = _translated(cia.text_zh)
    return _record(
        time, node, code, cia.source, cia.text, raw, name_zh=cia_zh, check=(check, check_zh)
    )


def decode_kinco_bits(profile: DriveData, detected: int) -> list[FaultEntry]:
    """The faults a Kinco 2600h:02 Detected_Faults value reports, lowest bit first."""
    return [e for e in profile.faults if e.kinco_bit and detected & e.kinco_bit]


def _matching(profile: DriveData, code: int, fmt: EmcyFormat) -> list[FaultEntry]:
    """Table entries an EMCY code stands for. Kinco sends only the low 16 bits of 603Fh, so
    0x2320 is any of 12320h/22320h/32320h; an exact code comes first."""
    if fmt is EmcyFormat.KINCO:
        found = [e for e in profile.faults if e.code & 0xFFFF == code]
        return sorted(found, key=lambda e: e.code != code)
    return [e for e in profile.faults if e.code == code]


def _vendor(
    time: float,
    node: int,
    code: int,
    entries: list[FaultEntry],
    profile: DriveData,
    raw: _Raw,
) -> FaultRecord:
    fmt = profile.quirks.emcy_format
    first = entries[0]
    names = " / ".join(e.name_en for e in entries)
    # each part in English and in Chinese (None: no Chinese for it)
    parts: list[tuple[str, str | None]] = [
        (f"Cause: {first.description}", _part_zh("原因：", first.description_zh))
    ]
    if len(entries) > 1:
        codes = ", ".join(f"{e.code:X}h" for e in entries)
        parts.append(
            (
                f"The EMCY carries only the low 16 bits of 603Fh ({codes} share them): read 603Fh"
                " or 2600h:02 to tell which.",
                f"EMCY 只携带 603Fh 的低 16 位（{codes.replace(', ', '、')} 共用）：读取 603Fh"
                " 或 2600h:02 以区分。",
            )
        )
    for entry in entries:
        check = entry.what_to_check.rstrip(".")
        check_zh = entry.what_to_check_zh
        if entry.kinco_bit:
            check += f" (2600h:02 bit {entry.kinco_bit:#x} {entry.name})"
            if check_zh is not None:
                bit = f"（2600h:02 位 {entry.kinco_bit:#x} {entry.name}）"
                check_zh = check_zh.rstrip(_END_ZH) + bit
        parts.append((f"Check: {check}.", _part_zh("检查：", check_zh)))
    cia = cia_text(first.emcy_code)
    cia_zh = cia.text_zh
    if cia.source is CodeSource.UNKNOWN:
        pass
    elif fmt is _ALARM:  # the drive sends no CiA code: the table's class is ServoDesk's own
        mapped_zh = f"ServoDesk 将其映射为 {first.emcy_code:04X}h {cia_zh}" if cia_zh else None
        parts.append(
            (
                f"CiA class: ServoDesk maps it to {first.emcy_code:04X}h {cia.text} (the drive's"
                " EMCY carries only the alarm number).",
                _part_zh("CiA 类别：", mapped_zh and f"{mapped_zh}（驱动器的 EMCY 只携带报警号）"),
            )
        )
    elif first.emcy_code != code:  # unless the vendor code is that CiA code itself
        parts.append(
            (
                f"CiA code {first.emcy_code:04X}h: {cia.text}.",
                _part_zh(f"CiA 代码 {first.emcy_code:04X}h：", cia_zh),
            )
        )
    unlisted = _NOT_IN_MANUAL.get((profile.profile, first.code))
    if unlisted is not None:
        unlisted_zh = _NOT_IN_MANUAL_ZH[(profile.profile, first.code)]
        parts.append(
            (
                f"Source: ServoDesk's simulated drive; {unlisted}.",
                f"来源：ServoDesk 仿真驱动器；{unlisted_zh}。",
            )
        )
    else:
        parts.append(
            (
                f"Source: {_MANUALS.get(profile.profile, 'the drive profile')}.",
                f"来源：{_MANUALS_ZH.get(profile.profile, '驱动器配置文件')}。",
            )
        )
    check_en = " ".join(en for en, _ in parts)
    zh = [text for _, text in parts]
    check_zh_all = None if None in zh else " ".join(t for t in zh if t is not None)
    return _record(
        time,
        node,
        code,
        CodeSource.VENDOR,
        names,
        raw,
        name_zh=_zh(entries),
        check=(check_en, check_zh_all),
    )


def _part_zh(label: str, text: str | None) -> str | None:
    """One Chinese part: its label, the text, a closing 。 unless it ends a sentence already;
    None when there is no Chinese text."""
    if text is None or not text.strip():
        return None
    text = text.strip()
    return f"{label}{text}" if text.endswith(tuple(_END_ZH)) else f"{label}{text}。"


def _zh(entries: list[FaultEntry]) -> tuple[str, str] | None:
    """The Chinese name of table entries and where it comes from: the manual's own Chinese
    name (MDi), else ServoDesk's translations (Kinco, CiA 402: all of them, or none)."""
    first = entries[0]
    if first.manual_chinese:
        return first.name, ZH_MANUAL
    translated = [e.name_zh for e in entries if e.name_zh]
    if len(translated) != len(entries):
        return None
    return " / ".join(translated), ZH_TRANSLATION


def _translated(text: str | None) -> tuple[str, str] | None:
    return (text, ZH_TRANSLATION) if text else None


def _record(
    time: float,
    node: int,
    code: int,
    source: CodeSource,
    name_en: str,
    raw: _Raw,
    *,
    name_zh: tuple[str, str] | None = None,  # (the name, ZH_MANUAL | ZH_TRANSLATION)
    check: tuple[str | None, str | None] = (None, None),  # (check, check_zh)
) -> FaultRecord:
    return FaultRecord(
        time=time,
        node=node,
        code=code,
        code_hex=f"0x{code:04X}",
        source=source.value,
        name_en=name_en,
        name_zh=name_zh[0] if name_zh else None,
        name_zh_source=name_zh[1] if name_zh else None,
        check=check[0],
        error_register=raw.error_register,
        manufacturer_hex=raw.manufacturer_hex,
        raw_hex=raw.raw_hex,
        check_zh=check[1] if check[0] is not None else None,
    )
