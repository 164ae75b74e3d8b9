"""The words the hand-over report writes itself, in English and Simplified Chinese (pure:
table-tested; every message id is in both languages).

Only the report's own words are here: headings, labels, column and row names, status words,
step titles, dates, the page footer. What users typed (record titles, names, notes, step
reasons) and what the drive or the record stored (device names, values, fault names, audit
actions, evidence notes) is data: the report shows it as stored, in whatever language it was
written, and never translates it. Evidence keys are the record's stored keys: the ones listed
here (`key.*`) get a Chinese label, any other is shown as its English title.

The Chinese step and status words are the Commission page's (frontend/src/i18n/locales,
`commission.stepTitle.*`, `status.*`), so the page and its report agree."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Final, Literal, get_args

from servodesk.models.commissioning import STEP_TITLES
from servodesk_protocol.pdo import (
    EVENT_DRIVEN,
    EVENT_RTR,
    SYNC_ACYCLIC,
    SYNC_CYCLIC_MAX,
    SYNC_RTR,
    Direction,
    transmission_words,
)

Lang = Literal["en", "zh-CN"]
LANGS: Final[tuple[Lang, ...]] = get_args(Lang)

_EN: dict[str, str] = {
    "date": "{Y}-{m}-{d} {H}:{M}:{S} UTC",
    # the page footer: a CSS `content` value
    "css.page": '"page " counter(page) " of " counter(pages)',
    "report.title": "Commissioning report: {title}",
    "report.machine": "Commissioning report: machine ({count} axes)",
    "report.made": "Commissioning report made by ServoDesk on {generated}.",
    "record.made": "Record {id}, made {created};",
    "record.status": "status",
    "node": "Node {node}",
    "heading.identity": "Identity",
    "heading.steps": "Steps",
    "heading.pdos": "PDO mapping",
    "heading.faults": "Faults during commissioning",
    "heading.audit": "Audit extract",
    "heading.notes": "Notes",
    "none.evidence": "No evidence recorded.",
    "none.pdos": "Not available.",
    "none.faults": "No faults since the record was made.",
    "none.audit": "No audit entries for this node since the record was made.",
    "sign.commissioned": "Commissioned by",
    "sign.accepted": "Accepted by",
    "sign.name": "Name",
    "sign.date": "Date",
    "sign.signature": "Signature",
    "status.to_do": "to do",
    "status.done": "done",
    "status.failed": "failed",
    "status.skipped": "skipped",
    "status.in_progress": "in progress",
    "yes": "yes",
    "no": "no",
    "unknown": "unknown",
    "none": "none",
    "col.step": "Step",
    "col.status": "Status",
    "col.by": "By",
    "col.at": "At",
    "col.reason": "Reason",
    "col.name": "Name",
    "col.value": "Value",
    "col.object": "Object",
    "col.old_new": "Old → new",
    "col.audit_id": "Audit id",
    "col.figure": "Figure",
    "col.unit": "Unit",
    "col.pdo": "PDO",
    "col.cob_id": "COB-ID",
    "col.valid": "Valid",
    "col.transmission": "Transmission",
    "col.event_timer": "Event timer",
    "col.mapping": "Mapping",
    "col.time": "Time",
    "col.code": "Code",
    "col.source": "Source",
    "col.fault": "Fault",
    "col.check": "Check",
    "col.state": "State",
    "col.id": "Id",
    "col.user_role": "User (role)",
    "col.action": "Action",
    "col.what": "What",
    "col.result": "Result",
    "table.evidence": "Evidence",
    "table.figures": "Figures",
    "table.changes": "Changes (audit log)",
    "table.faults": "Faults",
    "table.audit": "Audit log",
    "id.node": "Node",
    "id.name": "Device name (1008h)",
    "id.vendor": "Vendor id (1018h:01)",
    "id.product": "Product code (1018h:02)",
    "id.revision": "Revision (1018h:03)",
    "id.serial": "Serial (1018h:04)",
    "id.hardware": "Hardware (1009h)",
    "id.firmware": "Firmware (100Ah)",
    "id.device_type": "Device type (1000h)",
    "id.profile": "Profile",
    "id.dictionary": "Dictionary",
    "id.supported": "Supported modes (6502h)",
    "id.chosen": "Chosen modes",
    "user_role": "{user} ({role})",
    "pdo.mapped": "{object} {name} ({bits} bit)",
    "pdo.transmission": "{type} ({words})",
    "pdos.unread": "PDOs not read: {error}",
    "plot.title": "{title}: capture {id}",
    "plot.named": "{title}: capture {id} ({name})",
    "plot.failed": "capture {id}: no plot ({error})",
    "plot.empty": "capture {id}: no samples to plot",
    "plot.signal": "{name} (node {node})",
    "note": "{title}: {text}",
    **{f"step.{key}": title for key, title in STEP_TITLES.items()},
    # evidence keys as the English title the report made of them ("stop_time" → "Stop time")
    "key.values": "Values",
    "key.entries": "Entries",
    "key.objects": "Objects",
    "key.checked": "Checked",
    "key.lost": "Lost",
    "key.consumers": "Consumers",
    "key.jogs": "Jogs",
    "key.object": "Object",
    "key.name": "Name",
    "key.value": "Value",
    "key.expected": "Expected",
    "key.now": "Now",
    "key.old": "Old",
    "key.new": "New",
    "key.mode": "Mode",
    "key.modes": "Modes",
    "key.source": "Source",
    "key.note": "Note",
    "key.notes": "Notes",
    "key.index": "Index",
    "key.subindex": "Subindex",
    "key.unit": "Unit",
    "key.read": "Read",
    "key.written": "Written",
    "key.pdos": "Pdos",
    "key.coverage": "Coverage",
    "key.live": "Live",
    "key.audit_ids": "Audit ids",
    "key.text": "Text",
    "key.profile": "Profile",
    "key.profile_label": "Profile label",
    "key.eds": "Eds",
    "key.filename": "Filename",
    "key.node_id": "Node id",
    "key.bus_bitrate": "Bus bitrate",
    "key.drive_bitrate": "Drive bitrate",
    "key.heartbeat_producer_ms": "Heartbeat producer ms",
    "key.watching_tool": "Watching tool",
    "key.tool_node_id": "Tool node id",
    "key.not_supported": "Not supported",
}

_ZH: dict[str, str] = {
    "date": "{Y}年{m}月{d}日 {H}:{M}:{S} UTC",
    "css.page": '"第 " counter(page) " 页，共 " counter(pages) " 页"',
    "report.title": "调试报告：{title}",
    "report.machine": "调试报告：整机（{count} 个轴）",
    "report.made": "本调试报告由 ServoDesk 于 {generated} 生成。",
    "record.made": "记录 {id}，创建于 {created}；",
    "record.status": "状态",
    "node": "节点 {node}",
    "heading.identity": "设备标识",
    "heading.steps": "调试步骤",
    "heading.pdos": "PDO 映射",
    "heading.faults": "调试期间的故障",
    "heading.audit": "审计日志摘录",
    "heading.notes": "备注",
    "none.evidence": "未记录证据。",
    "none.pdos": "无法获取。",
    "none.faults": "自记录创建以来没有故障。",
    "none.audit": "自记录创建以来，此节点没有审计记录。",
    "sign.commissioned": "调试人",
    "sign.accepted": "验收人",
    "sign.name": "姓名",
    "sign.date": "日期",
    "sign.signature": "签名",
    "status.to_do": "待完成",
    "status.done": "已完成",
    "status.failed": "失败",
    "status.skipped": "已跳过",
    "status.in_progress": "进行中",
    "yes": "是",
    "no": "否",
    "unknown": "未知",
    "none": "无",
    "col.step": "步骤",
    "col.status": "状态",
    "col.by": "操作人",
    "col.at": "时间",
    "col.reason": "原因",
    "col.name": "名称",
    "col.value": "值",
    "col.object": "对象",
    "col.old_new": "原值 → 新值",
    "col.audit_id": "审计编号",
    "col.figure": "测量项",
    "col.unit": "单位",
    "col.pdo": "PDO",
    "col.cob_id": "COB-ID",
    "col.valid": "有效",
    "col.transmission": "传输方式",
    "col.event_timer": "事件定时器",
    "col.mapping": "映射",
    "col.time": "时间",
    "col.code": "代码",
    "col.source": "来源",
    "col.fault": "故障",
    "col.check": "检查",
    "col.state": "状态",
    "col.id": "编号",
    "col.user_role": "用户（角色）",
    "col.action": "操作",
    "col.what": "内容",
    "col.result": "结果",
    "table.evidence": "证据",
    "table.figures": "测量结果",
    "table.changes": "更改（审计日志）",
    "table.faults": "故障",
    "table.audit": "审计日志",
    "id.node": "节点",
    "id.name": "设备名称（1008h）",
    "id.vendor": "厂商 ID（1018h:01）",
    "id.product": "产品代码（1018h:02）",
    "id.revision": "版本号（1018h:03）",
    "id.serial": "序列号（1018h:04）",
    "id.hardware": "硬件版本（1009h）",
    "id.firmware": "固件版本（100Ah）",
    "id.device_type": "设备类型（1000h）",
    "id.profile": "设备子协议",
    "id.dictionary": "对象字典",
    "id.supported": "支持的模式（6502h）",
    "id.chosen": "所选模式",
    "user_role": "{user}（{role}）",
    "pdo.mapped": "{object} {name}（{bits} 位）",
    "pdo.transmission": "{type}：{words}",
    "pdos.unread": "未读取 PDO：{error}",
    "plot.title": "{title}：采集 {id}",
    "plot.named": "{title}：采集 {id}（{name}）",
    "plot.failed": "采集 {id}：无曲线（{error}）",
    "plot.empty": "采集 {id}：没有可绘制的采样",
    "plot.signal": "{name}（节点 {node}）",
    "note": "{title}：{text}",
    "step.identity": "识别",
    "step.communication": "通信",
    "step.parameters": "参数",
    "step.pdo": "PDO 映射",
    "step.limits": "限值",
    "step.stop_test": "停机测试",
    "step.test_move": "试运行",
    "step.homing": "回零",
    "step.store_verify": "保存并校验",
    "key.values": "读取的值",
    "key.entries": "建立记录以来的写入",
    "key.objects": "已更改的对象",
    "key.checked": "复位后回读",
    "key.lost": "复位后未保留",
    "key.consumers": "心跳消费者",
    "key.jogs": "点动",
    "key.object": "对象",
    "key.name": "名称",
    "key.value": "值",
    "key.expected": "期望值",
    "key.now": "当前值",
    "key.old": "原值",
    "key.new": "新值",
    "key.mode": "模式",
    "key.modes": "模式",
    "key.source": "来源",
    "key.note": "说明",
    "key.notes": "说明",
    "key.index": "索引",
    "key.subindex": "子索引",
    "key.unit": "单位",
    "key.read": "读取",
    "key.written": "写入",
    "key.pdos": "PDO",
    "key.coverage": "覆盖",
    "key.live": "实测",
    "key.audit_ids": "审计编号",
    "key.text": "文本",
    "key.profile": "设备子协议",
    "key.profile_label": "设备子协议名称",
    "key.eds": "EDS 文件",
    "key.filename": "文件名",
    "key.node_id": "节点号",
    "key.bus_bitrate": "总线波特率",
    "key.drive_bitrate": "驱动器波特率",
    "key.heartbeat_producer_ms": "心跳生产者周期 ms",
    "key.watching_tool": "监视本工具心跳",
    "key.tool_node_id": "本工具节点号",
    "key.not_supported": "不支持",
}

MESSAGES: Final[dict[Lang, dict[str, str]]] = {"en": _EN, "zh-CN": _ZH}


@dataclass(frozen=True)
class Words:
    """The report's words in one language; the template calls it: `t("heading.steps")`."""

    lang: Lang = "en"

    def __call__(self, message: str, **values: object) -> str:
        text = MESSAGES[self.lang][message]
        return text.format(**values) if values else text

    def when(self, stamp: float | None) -> str:
        """A UTC date and time ("" for none)."""
        if stamp is None:
            return ""
        t = time.gmtime(stamp)
        return self("date", Y=t.tm_year, m=f"{t.tm_mon:02d}", d=f"{t.tm_mday:02d}",
                    H=f"{t.tm_hour:02d}", M=f"{t.tm_min:02d}", S=f"{t.tm_sec:02d}")  # fmt: skip

    def yes_no(self, flag: bool) -> str:
        return self("yes" if flag else "no")

    def status(self, status: str) -> str:
        """A step's or record's status ("to_do", "in_progress", …) in words."""
        return MESSAGES[self.lang].get(f"status.{status}", status.replace("_", " "))

    def step_title(self, key: str, stored: str) -> str:
        """A step's title by its key; English is the title the record stored."""
        return stored if self.lang == "en" else MESSAGES[self.lang].get(f"step.{key}", stored)

    def key_title(self, key: str) -> str | None:
        """An evidence key's label, if listed (`key.*`); None: make the English title."""
        return MESSAGES[self.lang].get(f"key.{key}")

    def row_name(self, key: str) -> str:
        """A key of a nested evidence object as a row's name: English shows the key itself."""
        return key if self.lang == "en" else self.key_title(key) or key

    def transmission(self, transmission_type: int, direction: Direction) -> str:
        """A PDO transmission type in words (English: servodesk_protocol's)."""
        if self.lang == "en":
            return transmission_words(transmission_type, direction)
        return _zh_transmission(transmission_type, direction is Direction.TRANSMIT)


EN: Final = Words("en")


def words_for(lang: Lang = "en") -> Words:
    return Words(lang)


def _zh_transmission(t: int, tpdo: bool) -> str:
    """As the PDO page says it (pdo.zh-CN.json, `pdo.transmission.*`)."""
    if t == SYNC_ACYCLIC:
        return (
            "同步非循环（数据变化后的下一个 SYNC 时发送）"
            if tpdo
            else "同步（在下一个 SYNC 时生效）"
        )
    if t == 1:
        return "每个 SYNC"
    if t <= SYNC_CYCLIC_MAX:
        return f"每 {t} 个 SYNC" if tpdo else "同步"
    if t == SYNC_RTR:
        return "SYNC 时采样，远程请求时发送"
    if t == EVENT_RTR:
        return "远程请求时发送"
    if t in EVENT_DRIVEN:
        which = "制造商自定义" if t == 254 else "设备子协议定义"
        return f"变化时发送 + 事件定时器（{which}事件）" if tpdo else f"收到即生效（{which}事件）"
    return f"保留（{t}）"
