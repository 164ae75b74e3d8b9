"""EMCY error codes in words: the CiA 402 drive codes (also the values of 603Fh), the CiA 301
communication codes, the CiA 301 classes an unknown code falls into, and the error register
(1001h) bits. Pure lookups; the layering with a drive's own alarm table is the app's
(servodesk.faults.decode).

Sources (see the project's code tables): CiA 301 §7.2.7.1 classes and 81xx/82xx codes;
IEC 61800-7-201 (= CiA 402) error codes; CiA 301 §7.5.2.2 error register bits.

The sources are English only: each English table has a parallel Chinese one (the `_ZH` names),
ServoDesk's own translation, never the standard's words; the English tables stay the source's.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from enum import StrEnum
from types import MappingProxyType

from servodesk_protocol.emcy import ErrorRegister


class CodeSource(StrEnum):
    """Which table named a code (the API's `source`)."""

    VENDOR = "vendor"  # the drive's own alarm table (profile.toml)
    CIA402 = "cia402"
    CIA301 = "cia301"
    UNKNOWN = "unknown"  # in no table: only its class is known


RESET_TEXT = "Error reset / no error"
RESET_TEXT_ZH = "错误复位 / 无错误"  # ServoDesk's translation of RESET_TEXT


def _expand(rows: Iterable[tuple[int, int, str] | tuple[int, int, str, int]]) -> dict[int, str]:
    """(first, last, text[, first number]) rows -> {code: text}; a range names each code with
    its number ("Contact {n}": 5441h is contact 1)."""
    out: dict[int, str] = {}
    for first, last, text, *start in rows:
        number = start[0] if start else 1
        for code in range(first, last + 1):
            out[code] = text.format(n=code - first + number) if first != last else text
    return out


# CiA 402 / IEC 61800-7-201 drive error codes (exact codes; ranges expanded)
CIA402_CODES: Mapping[int, str] = MappingProxyType(
    _expand(
        [
            (0x2110, 0x2110, "Short circuit/earth leakage (input)"),
            (0x2120, 0x2120, "Earth leakage (input)"),
            (0x2121, 0x2123, "Earth leakage phase L{n}"),
            (0x2130, 0x2130, "Short circuit (input)"),
            (0x2131, 0x2131, "Short circuit phases L1-L2"),
            (0x2132, 0x2132, "Short circuit phases L2-L3"),
            (0x2133, 0x2133, "Short circuit phases L3-L1"),
            (0x2211, 0x2212, "Internal current no. {n}"),
            (0x2213, 0x2213, "Over-current in ramp function"),
            (0x2214, 0x2214, "Over-current in the sequence"),
            (0x2220, 0x2220, "Continuous over-current (device internal)"),
            (0x2221, 0x2222, "Continuous over-current no. {n}"),
            (0x2230, 0x2230, "Short circuit/earth leakage (device internal)"),
            (0x2240, 0x2240, "Earth leakage (device internal)"),
            (0x2250, 0x2250, "Short circuit (device internal)"),
            (0x2310, 0x2310, "Continuous over-current"),
            (0x2311, 0x2312, "Continuous over-current no. {n}"),
            (0x2320, 0x2320, "Short circuit/earth leakage (motor side)"),
            (0x2330, 0x2330, "Earth leakage (motor side)"),
            (0x2331, 0x2331, "Earth leakage phase U"),
            (0x2332, 0x2332, "Earth leakage phase V"),
            (0x2333, 0x2333, "Earth leakage phase W"),
            (0x2340, 0x2340, "Short circuit (motor side)"),
            (0x2341, 0x2341, "Short circuit phases U-V"),
            (0x2342, 0x2342, "Short circuit phases V-W"),
            (0x2343, 0x2343, "Short circuit phases W-U"),
            (0x2350, 0x2350, "Load level fault (I²t, thermal state)"),
            (0x2351, 0x2351, "Load level warning (I²t, thermal state)"),
            (0x3110, 0x3110, "Mains over-voltage"),
            (0x3111, 0x3113, "Mains over-voltage phase L{n}"),
            (0x3120, 0x3120, "Mains under-voltage"),
            (0x3121, 0x3123, "Mains under-voltage phase L{n}"),
            (0x3130, 0x3130, "Phase failure"),
            (0x3131, 0x3133, "Phase failure L{n}"),
            (0x3134, 0x3134, "Phase sequence"),
            (0x3140, 0x3140, "Mains frequency"),
            (0x3141, 0x3141, "Mains frequency too great"),
            (0x3142, 0x3142, "Mains frequency too small"),
            (0x3210, 0x3210, "DC-link over-voltage"),
            (0x3211, 0x3212, "Over-voltage no. {n}"),
            (0x3220, 0x3220, "DC-link under-voltage"),
            (0x3221, 0x3222, "Under-voltage no. {n}"),
            (0x3230, 0x3230, "Load error"),
            (0x3310, 0x3310, "Output over-voltage"),
            (0x3311, 0x3311, "Output over-voltage phase U"),
            (0x3312, 0x3312, "Output over-voltage phase V"),
            (0x3313, 0x3313, "Output over-voltage phase W"),
            (0x3320, 0x3320, "Armature circuit"),
            (0x3321, 0x3321, "Armature circuit interrupted"),
            (0x3330, 0x3330, "Field circuit"),
            (0x3331, 0x3331, "Field circuit interrupted"),
            (0x4110, 0x4110, "Excess ambient temperature"),
            (0x4120, 0x4120, "Too low ambient temperature"),
            (0x4130, 0x4130, "Temperature supply air"),
            (0x4140, 0x4140, "Temperature air outlet"),
            (0x4210, 0x4210, "Excess temperature device"),
            (0x4220, 0x4220, "Too low temperature device"),
            (0x4300, 0x4300, "Temperature drive"),
            (0x4310, 0x4310, "Excess temperature drive"),
            (0x4320, 0x4320, "Too low temperature drive"),
            (0x4400, 0x4400, "Temperature supply"),
            (0x4410, 0x4410, "Excess temperature supply"),
            (0x4420, 0x4420, "Too low temperature supply"),
            (0x5100, 0x5100, "Supply"),
            (0x5110, 0x5110, "Supply low voltage"),
            (0x5111, 0x5111, "U1 = ±15 V supply"),
            (0x5112, 0x5112, "U2 = +24 V supply"),
            (0x5113, 0x5113, "U3 = +5 V supply"),
            (0x5114, 0x5119, "Supply U{n} (manufacturer-specific)", 4),
            (0x5120, 0x5120, "Supply intermediate circuit"),
            (0x5200, 0x5200, "Control"),
            (0x5210, 0x5210, "Measurement circuit"),
            (0x5220, 0x5220, "Computing circuit"),
            (0x5300, 0x5300, "Operating unit"),
            (0x5400, 0x5400, "Power section"),
            (0x5410, 0x5410, "Output stages"),
            (0x5420, 0x5420, "Chopper"),
            (0x5430, 0x5430, "Input stages"),
            (0x5440, 0x5440, "Contacts"),
            (0x5441, 0x5445, "Contact {n} (manufacturer-specific)"),
            (0x5450, 0x5450, "Fuses"),
            (0x5451, 0x5453, "Fuse S{n} = L{n}"),
            (0x5454, 0x5459, "Fuse S{n} (manufacturer-specific)", 4),
            (0x5500, 0x5500, "Hardware memory"),
            (0x5510, 0x5510, "RAM"),
            (0x5520, 0x5520, "ROM/EPROM"),
            (0x5530, 0x5530, "EEPROM"),
            (0x6010, 0x6010, "Software reset (watchdog)"),
            (0x6301, 0x630F, "Data record no. {n}"),
            (0x6310, 0x6310, "Loss of parameters"),
            (0x6320, 0x6320, "Parameter error"),
            (0x7100, 0x7100, "Power"),
            (0x7110, 0x7110, "Brake chopper"),
            (0x7111, 0x7111, "Failure brake chopper"),
            (0x7112, 0x7112, "Over-current brake chopper"),
            (0x7113, 0x7113, "Protective circuit brake chopper"),
            (0x7120, 0x7120, "Motor"),
            (0x7121, 0x7121, "Motor blocked"),
            (0x7122, 0x7122, "Motor error or commutation malfunction"),
            (0x7123, 0x7123, "Motor tilted"),
            (0x7200, 0x7200, "Measurement circuit"),
            (0x7300, 0x7300, "Sensor"),
            (0x7301, 0x7301, "Tacho fault"),
            (0x7302, 0x7302, "Tacho wrong polarity"),
            (0x7303, 0x7304, "Resolver {n} fault"),
            (0x7305, 0x7307, "Incremental sensor {n} fault"),
            (0x7310, 0x7310, "Speed"),
            (0x7320, 0x7320, "Position"),
            (0x7400, 0x7400, "Computation circuit"),
            (0x7500, 0x7500, "Communication"),
            (0x7510, 0x7510, "Serial interface no. 1"),
            (0x7520, 0x7520, "Serial interface no. 2"),
            (0x7600, 0x7600, "Data storage (external)"),
            (0x8300, 0x8300, "Torque control"),
            (0x8311, 0x8311, "Excess torque"),
            (0x8312, 0x8312, "Difficult start-up"),
            (0x8313, 0x8313, "Standstill torque"),
            (0x8321, 0x8321, "Insufficient torque"),
            (0x8331, 0x8331, "Torque fault"),
            (0x8400, 0x8400, "Velocity speed controller"),
            (0x8500, 0x8500, "Position controller"),
            (0x8600, 0x8600, "Positioning controller"),
            (0x8611, 0x8611, "Following error"),
            (0x8612, 0x8612, "Reference limit"),
            (0x8700, 0x8700, "Sync controller"),
            (0x8800, 0x8800, "Winding controller"),
            (0x8900, 0x8900, "Process data monitoring"),
            (0x8A00, 0x8A00, "Control"),
            (0xF001, 0xF001, "Deceleration"),
            (0xF002, 0xF002, "Sub-synchronous run"),
            (0xF003, 0xF003, "Stroke operation"),
            (0xF004, 0xF004, "Control"),
        ]
    )
)

# CIA402_CODES in Chinese, row for row (ServoDesk's translation: the standard is English only)
CIA402_CODES_ZH: Mapping[int, str] = MappingProxyType(
    _expand(
        [
            (0x2110, 0x2110, "短路/接地漏电（输入侧）"),
            (0x2120, 0x2120, "接地漏电（输入侧）"),
            (0x2121, 0x2123, "L{n} 相接地漏电"),
            (0x2130, 0x2130, "短路（输入侧）"),
            (0x2131, 0x2131, "L1-L2 相间短路"),
            (0x2132, 0x2132, "L2-L3 相间短路"),
            (0x2133, 0x2133, "L3-L1 相间短路"),
            (0x2211, 0x2212, "内部电流 {n}"),
            (0x2213, 0x2213, "斜坡过程中过流"),
            (0x2214, 0x2214, "运行过程中过流"),
            (0x2220, 0x2220, "持续过流（设备内部）"),
            (0x2221, 0x2222, "持续过流 {n}"),
            (0x2230, 0x2230, "短路/接地漏电（设备内部）"),
            (0x2240, 0x2240, "接地漏电（设备内部）"),
            (0x2250, 0x2250, "短路（设备内部）"),
            (0x2310, 0x2310, "持续过流"),
            (0x2311, 0x2312, "持续过流 {n}"),
            (0x2320, 0x2320, "短路/接地漏电（电机侧）"),
            (0x2330, 0x2330, "接地漏电（电机侧）"),
            (0x2331, 0x2331, "U 相接地漏电"),
            (0x2332, 0x2332, "V 相接地漏电"),
            (0x2333, 0x2333, "W 相接地漏电"),
            (0x2340, 0x2340, "短路（电机侧）"),
            (0x2341, 0x2341, "U-V 相间短路"),
            (0x2342, 0x2342, "V-W 相间短路"),
            (0x2343, 0x2343, "W-U 相间短路"),
            (0x2350, 0x2350, "负载率故障（I²t，热状态）"),
            (0x2351, 0x2351, "负载率警告（I²t，热状态）"),
            (0x3110, 0x3110, "电网过压"),
            (0x3111, 0x3113, "电网 L{n} 相过压"),
            (0x3120, 0x3120, "电网欠压"),
            (0x3121, 0x3123, "电网 L{n} 相欠压"),
            (0x3130, 0x3130, "缺相"),
            (0x3131, 0x3133, "L{n} 缺相"),
            (0x3134, 0x3134, "相序错误"),
            (0x3140, 0x3140, "电网频率异常"),
            (0x3141, 0x3141, "电网频率过高"),
            (0x3142, 0x3142, "电网频率过低"),
            (0x3210, 0x3210, "直流母线过压"),
            (0x3211, 0x3212, "过压 {n}"),
            (0x3220, 0x3220, "直流母线欠压"),
            (0x3221, 0x3222, "欠压 {n}"),
            (0x3230, 0x3230, "负载错误"),
            (0x3310, 0x3310, "输出过压"),
            (0x3311, 0x3311, "U 相输出过压"),
            (0x3312, 0x3312, "V 相输出过压"),
            (0x3313, 0x3313, "W 相输出过压"),
            (0x3320, 0x3320, "电枢回路"),
            (0x3321, 0x3321, "电枢回路断路"),
            (0x3330, 0x3330, "励磁回路"),
            (0x3331, 0x3331, "励磁回路断路"),
            (0x4110, 0x4110, "环境温度过高"),
            (0x4120, 0x4120, "环境温度过低"),
            (0x4130, 0x4130, "进风温度"),
            (0x4140, 0x4140, "出风温度"),
            (0x4210, 0x4210, "设备温度过高"),
            (0x4220, 0x4220, "设备温度过低"),
            (0x4300, 0x4300, "驱动温度"),
            (0x4310, 0x4310, "驱动温度过高"),
            (0x4320, 0x4320, "驱动温度过低"),
            (0x4400, 0x4400, "电源温度"),
            (0x4410, 0x4410, "电源温度过高"),
            (0x4420, 0x4420, "电源温度过低"),
            (0x5100, 0x5100, "电源"),
            (0x5110, 0x5110, "低压电源"),
            (0x5111, 0x5111, "U1 = ±15 V 电源"),
            (0x5112, 0x5112, "U2 = +24 V 电源"),
            (0x5113, 0x5113, "U3 = +5 V 电源"),
            (0x5114, 0x5119, "U{n} 电源（制造商自定义）", 4),
            (0x5120, 0x5120, "中间回路电源"),
            (0x5200, 0x5200, "控制"),
            (0x5210, 0x5210, "测量电路"),
            (0x5220, 0x5220, "运算电路"),
            (0x5300, 0x5300, "操作单元"),
            (0x5400, 0x5400, "功率部分"),
            (0x5410, 0x5410, "输出级"),
            (0x5420, 0x5420, "斩波器"),
            (0x5430, 0x5430, "输入级"),
            (0x5440, 0x5440, "触点"),
            (0x5441, 0x5445, "触点 {n}（制造商自定义）"),
            (0x5450, 0x5450, "熔断器"),
            (0x5451, 0x5453, "熔断器 S{n} = L{n}"),
            (0x5454, 0x5459, "熔断器 S{n}（制造商自定义）", 4),
            (0x5500, 0x5500, "硬件存储器"),
            (0x5510, 0x5510, "RAM 存储器"),
            (0x5520, 0x5520, "ROM/EPROM 存储器"),
            (0x5530, 0x5530, "EEPROM 存储器"),
            (0x6010, 0x6010, "软件复位（看门狗）"),
            (0x6301, 0x630F, "数据记录 {n}"),
            (0x6310, 0x6310, "参数丢失"),
            (0x6320, 0x6320, "参数错误"),
            (0x7100, 0x7100, "功率"),
            (0x7110, 0x7110, "制动斩波器"),
            (0x7111, 0x7111, "制动斩波器失效"),
            (0x7112, 0x7112, "制动斩波器过流"),
            (0x7113, 0x7113, "制动斩波器保护电路"),
            (0x7120, 0x7120, "电机"),
            (0x7121, 0x7121, "电机堵转"),
            (0x7122, 0x7122, "电机故障或换相异常"),
            (0x7123, 0x7123, "电机失步（倾覆）"),
            (0x7200, 0x7200, "测量电路"),
            (0x7300, 0x7300, "传感器"),
            (0x7301, 0x7301, "测速发电机故障"),
            (0x7302, 0x7302, "测速发电机极性错误"),
            (0x7303, 0x7304, "旋转变压器 {n} 故障"),
            (0x7305, 0x7307, "增量编码器 {n} 故障"),
            (0x7310, 0x7310, "速度"),
            (0x7320, 0x7320, "位置"),
            (0x7400, 0x7400, "运算电路"),
            (0x7500, 0x7500, "通信"),
            (0x7510, 0x7510, "串行接口 1"),
            (0x7520, 0x7520, "串行接口 2"),
            (0x7600, 0x7600, "数据存储（外部）"),
            (0x8300, 0x8300, "转矩控制"),
            (0x8311, 0x8311, "转矩过大"),
            (0x8312, 0x8312, "启动困难"),
            (0x8313, 0x8313, "静止转矩"),
            (0x8321, 0x8321, "转矩不足"),
            (0x8331, 0x8331, "转矩故障"),
            (0x8400, 0x8400, "速度控制器"),
            (0x8500, 0x8500, "位置控制器"),
            (0x8600, 0x8600, "定位控制器"),
            (0x8611, 0x8611, "跟随误差过大"),
            (0x8612, 0x8612, "参考限位"),
            (0x8700, 0x8700, "同步控制器"),
            (0x8800, 0x8800, "卷绕控制器"),
            (0x8900, 0x8900, "过程数据监控"),
            (0x8A00, 0x8A00, "控制"),
            (0xF001, 0xF001, "减速"),
            (0xF002, 0xF002, "次同步运行"),
            (0xF003, 0xF003, "冲程运行"),
            (0xF004, 0xF004, "控制"),
        ]
    )
)

# CiA 301 §7.2.7.1: the communication and protocol codes it names exactly
CIA301_CODES: Mapping[int, str] = MappingProxyType(
    {
        0x1000: "Generic error",
        0x8110: "CAN overrun (objects lost)",
        0x8120: "CAN in error-passive mode",
        0x8130: "Life guard error or heartbeat error",
        0x8140: "Recovered from bus-off",
        0x8150: "CAN-ID collision",
        0x8210: "PDO not processed due to length error",
        0x8220: "PDO length exceeded",
        0x8230: "DAM MPDO not processed, destination object not available",
        0x8240: "Unexpected SYNC data length",
        0x8250: "RPDO timeout",
    }
)

# CIA301_CODES in Chinese (ServoDesk's translation)
CIA301_CODES_ZH: Mapping[int, str] = MappingProxyType(
    {
        0x1000: "通用错误",
        0x8110: "CAN 溢出（对象丢失）",
        0x8120: "CAN 处于错误被动状态",
        0x8130: "节点保护错误或心跳错误",
        0x8140: "已从总线关闭（bus-off）恢复",
        0x8150: "CAN-ID 冲突",
        0x8210: "PDO 因长度错误未处理",
        0x8220: "PDO 长度超出",
        0x8230: "DAM MPDO 未处理：目标对象不存在",
        0x8240: "SYNC 数据长度不符",
        0x8250: "RPDO 超时",
    }
)

# CiA 301 classes by the code's high byte (xx00 ranges) and, failing that, its high nibble
_BYTE_CLASSES: Mapping[int, str] = MappingProxyType(
    {
        0x21: "current, device input side",
        0x22: "current inside the device",
        0x23: "current, device output side",
        0x31: "mains voltage",
        0x32: "voltage inside the device",
        0x33: "output voltage",
        0x41: "ambient temperature",
        0x42: "device temperature",
        0x61: "internal software",
        0x62: "user software",
        0x63: "data set",
        0x81: "communication",
        0x82: "protocol error",
        0xF0: "additional functions",
        0xFF: "device specific",
    }
)
_NIBBLE_CLASSES: Mapping[int, str] = MappingProxyType(
    {
        0x1: "generic error",
        0x2: "current",
        0x3: "voltage",
        0x4: "temperature",
        0x5: "device hardware",
        0x6: "device software",
        0x7: "additional modules",
        0x8: "monitoring",
        0x9: "external error",
        0xF: "additional functions",
    }
)

# the classes in Chinese (ServoDesk's translation), key for key
_BYTE_CLASSES_ZH: Mapping[int, str] = MappingProxyType(
    {
        0x21: "电流，设备输入侧",
        0x22: "设备内部电流",
        0x23: "电流，设备输出侧",
        0x31: "电网电压",
        0x32: "设备内部电压",
        0x33: "输出电压",
        0x41: "环境温度",
        0x42: "设备温度",
        0x61: "内部软件",
        0x62: "用户软件",
        0x63: "数据集",
        0x81: "通信",
        0x82: "协议错误",
        0xF0: "附加功能",
        0xFF: "设备自定义",
    }
)
_NIBBLE_CLASSES_ZH: Mapping[int, str] = MappingProxyType(
    {
        0x1: "通用错误",
        0x2: "电流",
        0x3: "电压",
        0x4: "温度",
        0x5: "设备硬件",
        0x6: "设备软件",
        0x7: "附加模块",
        0x8: "监控",
        0x9: "外部错误",
        0xF: "附加功能",
    }
)

# 1001h bits in words (CiA 301 §7.5.2.2)
ERROR_REGISTER_BITS: tuple[tuple[ErrorRegister, str], ...] = (
    (ErrorRegister.GENERIC, "generic"),
    (ErrorRegister.CURRENT, "current"),
    (ErrorRegister.VOLTAGE, "voltage"),
    (ErrorRegister.TEMPERATURE, "temperature"),
    (ErrorRegister.COMMUNICATION, "communication"),
    (ErrorRegister.DEVICE_PROFILE, "device profile"),
    (ErrorRegister.RESERVED, "reserved bit 6"),
    (ErrorRegister.MANUFACTURER, "manufacturer"),
)
# ERROR_REGISTER_BITS in Chinese (ServoDesk's translation), bit for bit
ERROR_REGISTER_BITS_ZH: tuple[tuple[ErrorRegister, str], ...] = (
    (ErrorRegister.GENERIC, "通用"),
    (ErrorRegister.CURRENT, "电流"),
    (ErrorRegister.VOLTAGE, "电压"),
    (ErrorRegister.TEMPERATURE, "温度"),
    (ErrorRegister.COMMUNICATION, "通信"),
    (ErrorRegister.DEVICE_PROFILE, "设备子协议"),
    (ErrorRegister.RESERVED, "保留位 6"),
    (ErrorRegister.MANUFACTURER, "制造商自定义"),
)


def is_reset(code: int) -> bool:
    """00xxh: "error reset or no error" (CiA 301; python-canopen tests the high byte too)."""
    return code & 0xFF00 == 0


def code_class(code: int) -> str:
    """The CiA 301 class of any EMCY code, most specific first: 0x8130 -> "monitoring /
    communication", 0x5123 -> "device hardware", 0x0000 -> "error reset"."""
    if is_reset(code):
        return "error reset"
    nibble = _NIBBLE_CLASSES.get(code >> 12)
    specific = _BYTE_CLASSES.get(code >> 8)
    if specific is None:
        return nibble or "reserved"
    if _specific_alone(code):
        return specific
    return f"{nibble} / {specific}"


def code_class_zh(code: int) -> str:
    """code_class in Chinese (ServoDesk's translation): 0x8130 -> "监控 / 通信"."""
    if is_reset(code):
        return "错误复位"
    nibble = _NIBBLE_CLASSES_ZH.get(code >> 12)
    specific = _BYTE_CLASSES_ZH.get(code >> 8)
    if specific is None:
        return nibble or "保留"
    if _specific_alone(code):
        return specific
    return f"{nibble} / {specific}"


def _specific_alone(code: int) -> bool:
    """Whether a code with a byte class is named by it alone: no nibble class, an Fxxx code
    (own classes), or a byte class that repeats its nibble's ("current, device input side")."""
    nibble = _NIBBLE_CLASSES.get(code >> 12)
    specific = _BYTE_CLASSES.get(code >> 8, "")
    return nibble is None or code >> 12 == 0xF or specific.startswith(nibble)


@dataclass(frozen=True, slots=True)
class CodeText:
    source: CodeSource
    text: str  # what the table says; for an unknown code its class
    code_class: str
    # the text in Chinese: ServoDesk's translation (the tables are English only); None: none
    text_zh: str | None = None


def describe(code: int, *, cia402: bool = True) -> CodeText:
    """A CiA EMCY code in words: the CiA 402 table (when the device is a drive), then CiA 301,
    then the class alone ("Unknown monitoring code 0x8F01"): never nothing. `cia402` False
    skips the drive table, whose codes mean other things for CiA 401 I/O devices."""
    cls = code_class(code)
    if is_reset(code):
        return CodeText(CodeSource.CIA301, RESET_TEXT, cls, RESET_TEXT_ZH)
    if cia402 and code in CIA402_CODES:
        return CodeText(CodeSource.CIA402, CIA402_CODES[code], cls, CIA402_CODES_ZH[code])
    if code in CIA301_CODES:
        return CodeText(CodeSource.CIA301, CIA301_CODES[code], cls, CIA301_CODES_ZH[code])
    if code >= 0xFF00:  # CiA 301 and CiA 402 leave FFxxh to the manufacturer
        text = f"Manufacturer-specific code 0x{code:04X}"
        return CodeText(CodeSource.UNKNOWN, text, cls, f"制造商自定义代码 0x{code:04X}")
    text_zh = f"未知代码 0x{code:04X}（{code_class_zh(code)}）"
    return CodeText(CodeSource.UNKNOWN, f"Unknown {cls} code 0x{code:04X}", cls, text_zh)


def error_register_words(register: int) -> list[str]:
    """The set 1001h bits in words, bit 0 first: 0x21 -> ["generic", "device profile"]."""
    return [words for bit, words in ERROR_REGISTER_BITS if register & bit]


def error_register_words_zh(register: int) -> list[str]:
    """error_register_words in Chinese: 0x21 -> ["通用", "设备子协议"]."""
    return [words for bit, words in ERROR_REGISTER_BITS_ZH if register & bit]
