// Faults in words for the banner, the Faults tab and the history table. Pure, table-tested.
import type { Fault } from "../api/faults";
import { currentLanguage, i18n, type Language, type MessageKey } from "../i18n";
import { stateWords } from "./serverText";

/** CiA 301 error register 1001h, bit 0 first. */
const ERROR_REGISTER_BITS: readonly MessageKey[] = [
  "faults.words.register.generic",
  "faults.words.register.current",
  "faults.words.register.voltage",
  "faults.words.register.temperature",
  "faults.words.register.communication",
  "faults.words.register.deviceProfile",
  "faults.words.register.reserved6",
  "faults.words.register.manufacturer",
];

/** The set 1001h bits in words, bit 0 first: 0x21 → ["generic", "device profile"]. */
export function errorRegisterWords(register: number): string[] {
  return ERROR_REGISTER_BITS.filter((_, bit) => (register & (1 << bit)) !== 0).map((key) =>
    i18n.t(key),
  );
}

/** "21h: generic, device profile"; "00h: no error"; "—" when the frame carries none. */
export function errorRegisterText(register: number | null | undefined): string {
  if (register == null) return "—";
  const hexText = `${register.toString(16).toUpperCase().padStart(2, "0")}h`;
  const words = errorRegisterWords(register);
  const separator = i18n.t("faults.words.listSeparator");
  return `${hexText}: ${words.length ? words.join(separator) : i18n.t("faults.words.noError")}`;
}

const SOURCE_LABELS: Record<string, MessageKey> = {
  vendor: "faults.words.source.vendor",
  cia402: "faults.words.source.cia402",
  cia301: "faults.words.source.cia301",
  unknown: "faults.words.source.unknown",
};

export function sourceLabel(source: string): string {
  const key = SOURCE_LABELS[source];
  return key ? i18n.t(key) : source;
}

/**
 * Whether the code is a drive's alarm number (MDi-S1-C sends 2 bytes: the alarm) rather than an
 * EMCY code. EMCY codes below 1000h are "no error / reset" only, so a vendor code there is an
 * alarm number.
 */
export function isAlarmNumber(fault: Pick<Fault, "code" | "source">): boolean {
  return fault.source === "vendor" && fault.code > 0 && fault.code < 0x1000;
}

/** "alarm 4" for an alarm number, "0x8611" for an EMCY code. */
export function faultCode(fault: Pick<Fault, "code" | "code_hex" | "source">): string {
  return isAlarmNumber(fault) ? i18n.t("faults.words.alarm", { n: fault.code }) : fault.code_hex;
}

type FaultNames = Pick<Fault, "name_en" | "name_zh" | "name_zh_source">;

/** Whether ServoDesk translated the Chinese name (the source, Kinco's manual or a CiA table, is
 * English only), rather than it being the drive manual's own (MDi-S1-C). */
export function isTranslatedName(fault: FaultNames): boolean {
  return Boolean(fault.name_zh) && fault.name_zh_source === "translation";
}

/** Whether the Chinese name shows: the manual's own always (as in English before), ServoDesk's
 * translation only in Chinese. */
export function showsChineseName(
  fault: FaultNames,
  language: Language = currentLanguage(),
): boolean {
  if (!fault.name_zh) return false;
  return language === "zh-CN" || !isTranslatedName(fault);
}

/** In Chinese the Chinese name alone ("位置超差"; the source's words stay on the Faults tab's
 * details); in English "位置超差 Following error" for a manual's own Chinese name, the English
 * alone for a name ServoDesk translated. */
export function faultName(fault: FaultNames, language: Language = currentLanguage()): string {
  if (!showsChineseName(fault, language)) return fault.name_en;
  return language === "zh-CN" ? (fault.name_zh ?? "") : `${fault.name_zh} ${fault.name_en}`;
}

/** The table a name comes from, for the translation marker's title: the "Source" of the check
 * text (the drive's manual), else the CiA table; in the page's language. */
export function nameSource(
  fault: Pick<Fault, "check" | "check_zh" | "source">,
  language: Language = currentLanguage(),
): string {
  const source = faultCheckParts(fault, language).find((part) => part.key === "source")?.text;
  const table = source
    ?.split(/[;；]/)[0]
    ?.replace(/[.。]$/, "")
    .trim();
  return table || sourceLabel(fault.source);
}

/** "alarm 4 位置超差 Following error". */
export function faultWords(fault: Fault): string {
  return `${faultCode(fault)} ${faultName(fault)}`;
}

/** The banner's line: "Node 1 in fault: alarm 4 位置超差 Following error". */
export function bannerText(fault: Fault): string {
  return `Node ${fault.node} in fault: ${faultWords(fault)}`;
}

export interface CheckPart {
  /** "Cause", "Check", "CiA code 8611h", "Source" (原因, 检查, CiA 代码 8611h, 来源 in the
   * Chinese text); "" for text before any label. */
  label: string;
  /** What the label says whatever the language: "source" for Source and 来源. */
  key: string;
  text: string;
}

const CHECK_LABEL =
  /(?:^|\s)(Cause|Check|Source|CiA class|CiA code [0-9A-F]+h|Error register [0-9A-F]+h):\s/g;
// the server's check_zh: the same parts with Chinese labels and full-width colons
const CHECK_LABEL_ZH =
  /(?:^|\s)(原因|检查|来源|CiA 类别|CiA 代码 [0-9A-F]+h|错误寄存器 [0-9A-F]+h)：/g;
const LABEL_KEYS: Record<string, string> = {
  Cause: "cause",
  原因: "cause",
  Check: "check",
  检查: "check",
  Source: "source",
  来源: "source",
};

/** The fault's "what to check" parts in the page's language: the server's Chinese `check_zh`
 * in Chinese when it has one, else its English `check`. */
export function faultCheckParts(
  fault: Pick<Fault, "check" | "check_zh">,
  language: Language = currentLanguage(),
): CheckPart[] {
  if (language === "zh-CN" && fault.check_zh) return checkParts(fault.check_zh, CHECK_LABEL_ZH);
  return checkParts(fault.check);
}

/**
 * The server's "what to check" text, split at its labels ("Cause: … Check: … Source: …") so the
 * page can show it as a list; text without labels comes back as one unlabelled part.
 */
export function checkParts(check: string | null | undefined, labels = CHECK_LABEL): CheckPart[] {
  if (!check?.trim()) return [];
  const marks = [...check.matchAll(labels)].map((m) => ({
    label: m[1] ?? "",
    start: m.index,
    textStart: m.index + m[0].length,
  }));
  const parts: CheckPart[] = [];
  const lead = check.slice(0, marks[0]?.start ?? check.length).trim();
  if (lead) parts.push({ label: "", key: "", text: lead });
  marks.forEach((mark, i) => {
    const text = check.slice(mark.textStart, marks[i + 1]?.start ?? check.length).trim();
    if (text) parts.push({ label: mark.label, key: LABEL_KEYS[mark.label] ?? "", text });
  });
  return parts;
}

/** Newest first; the server's order is kept for equal times. */
export function newestFirst<T extends { time: number }>(items: readonly T[]): T[] {
  return items
    .map((item, i) => ({ item, i }))
    .sort((a, b) => b.item.time - a.item.time || a.i - b.i)
    .map(({ item }) => item);
}

/** "2026-11-25 07:12:03.120" in local time. */
export function formatDateTime(unixSeconds: number): string {
  const date = new Date(unixSeconds * 1000);
  const pad = (n: number, w = 2): string => String(n).padStart(w, "0");
  const day = `${date.getFullYear()}-${pad(date.getMonth() + 1)}-${pad(date.getDate())}`;
  const clock = `${pad(date.getHours())}:${pad(date.getMinutes())}:${pad(date.getSeconds())}`;
  return `${day} ${clock}.${pad(date.getMilliseconds(), 3)}`;
}

/** 603Fh in words: "0x0000" "no error"; "0x0004" "alarm 4 位置超差 Following error" when it is
 * the active fault's code (MDi: the alarm number; Kinco: the low 16 bits); words null else. */
export function errorCodeParts(
  value: number | string | null | undefined,
  active: Fault | null | undefined,
): { hex: string; words: string | null } {
  if (typeof value !== "number") return { hex: value ?? "—", words: null };
  const hexText = `0x${value.toString(16).toUpperCase().padStart(4, "0")}`;
  if (value === 0) return { hex: hexText, words: i18n.t("faults.words.noError") };
  if (!active || (active.code & 0xffff) !== value) return { hex: hexText, words: null };
  // the name alone when the code reads the same; else the code as the drive's table has it
  const words = faultCode(active) === hexText ? faultName(active) : faultWords(active);
  return { hex: hexText, words };
}

/** A state the fault record holds in the page's language; one ServoDesk did not see reads
 * "not seen". */
function seenState(state: string | null | undefined): string {
  return state ? stateWords(state) : i18n.t("faults.words.notSeen");
}

/** "Operation enabled → Fault"; a state ServoDesk did not see reads "not seen". */
export function stateChange(fault: Pick<Fault, "state_before" | "state_after">): string {
  if (!fault.state_before && !fault.state_after) return "—";
  return `${seenState(fault.state_before)} → ${seenState(fault.state_after)}`;
}

/** SDO aborts meaning "the drive has no such object": 06020000h, 06090011h. */
export function hasNoObject(abortCode: string | null | undefined): boolean {
  if (!abortCode) return false;
  const value = Number.parseInt(abortCode.replace(/^0x/i, ""), 16);
  return value === 0x06020000 || value === 0x06090011;
}
