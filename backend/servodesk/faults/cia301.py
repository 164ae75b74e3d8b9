"""CiA 301's generic emergency error codes (CiA 301 Table 21, the xx00h heads of each class):
what servodesk_protocol.emcy_codes names exactly (its 81xxh/82xxh codes) plus the class heads
a device sends when it says no more than the class (2000h "Current – generic error").

A code in no table keeps the most specific class it falls into ("Unknown monitoring /
communication code 0x81FD", servodesk_protocol.emcy_codes.describe).

Like the tables it extends, GENERIC_CODES is English; GENERIC_CODES_ZH is ServoDesk's Chinese
translation of it, key for key.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from servodesk_protocol.emcy_codes import CodeSource, CodeText, code_class, describe

# CiA 301 Table 21 (the project's code tables, (b1)): the generic code of each class
GENERIC_CODES: Mapping[int, str] = MappingProxyType(
    {
        0x1000: "Generic error",
        0x2000: "Current – generic error",
        0x2100: "Current, device input side – generic",
        0x2200: "Current inside the device – generic",
        0x2300: "Current, device output side – generic",
        0x3000: "Voltage – generic error",
        0x3100: "Mains voltage – generic",
        0x3200: "Voltage inside the device – generic",
        0x3300: "Output voltage – generic",
        0x4000: "Temperature – generic error",
        0x4100: "Ambient temperature – generic",
        0x4200: "Device temperature – generic",
        0x5000: "Device hardware – generic error",
        0x6000: "Device software – generic error",
        0x6100: "Internal software – generic",
        0x6200: "User software – generic",
        0x6300: "Data set – generic",
        0x7000: "Additional modules – generic error",
        0x8000: "Monitoring – generic error",
        0x8100: "Communication – generic",
        0x8200: "Protocol error – generic",
        0x9000: "External error – generic error",
        0xF000: "Additional functions – generic error",
        0xFF00: "Device specific – generic error",
    }
)


# GENERIC_CODES in Chinese (ServoDesk's translation)
GENERIC_CODES_ZH: Mapping[int, str] = MappingProxyType(
    {
        0x1000: "通用错误",
        0x2000: "电流 – 通用错误",
        0x2100: "电流，设备输入侧 – 通用",
        0x2200: "设备内部电流 – 通用",
        0x2300: "电流，设备输出侧 – 通用",
        0x3000: "电压 – 通用错误",
        0x3100: "电网电压 – 通用",
        0x3200: "设备内部电压 – 通用",
        0x3300: "输出电压 – 通用",
        0x4000: "温度 – 通用错误",
        0x4100: "环境温度 – 通用",
        0x4200: "设备温度 – 通用",
        0x5000: "设备硬件 – 通用错误",
        0x6000: "设备软件 – 通用错误",
        0x6100: "内部软件 – 通用",
        0x6200: "用户软件 – 通用",
        0x6300: "数据集 – 通用",
        0x7000: "附加模块 – 通用错误",
        0x8000: "监控 – 通用错误",
        0x8100: "通信 – 通用",
        0x8200: "协议错误 – 通用",
        0x9000: "外部错误 – 通用错误",
        0xF000: "附加功能 – 通用错误",
        0xFF00: "设备自定义 – 通用错误",
    }
)


def cia_text(code: int, *, cia402: bool = True) -> CodeText:
    """A CiA EMCY code in words: CiA 402 (for a drive), CiA 301's exact codes, the generic code
    of a class, then the class alone."""
    found = describe(code, cia402=cia402)
    if found.source is CodeSource.UNKNOWN and code in GENERIC_CODES:
        text, text_zh = GENERIC_CODES[code], GENERIC_CODES_ZH[code]
        return CodeText(CodeSource.CIA301, text, code_class(code), text_zh)
    return found
