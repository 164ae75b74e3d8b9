// The PDO page in Simplified Chinese: cards, byte layout, bus load, the draft and its editor,
// the apply dialog and its result, the live check and SYNC from the zh-CN catalogue; object
// names, procedures, problems and notes stay as the server sends them; none of the page's
// English texts left, no bare catalogue key anywhere.
import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import { json, stubFetch, type Handler } from "../../test/fetchStub";
import { LiveStore } from "../../live/store";
import { inChinese } from "../../test/inChinese";
import { pageWords } from "../../test/pageWords";
import { renderPage } from "../../test/render";
import { DEVICE, INFO, LIVE, LOAD, loadFor, RECOMMENDED, RULES, TREE } from "./fixtures";
import { PdoPage } from "./PdoPage";
import type { Validation } from "./types";

inChinese();

/** The page's English texts, replaced by the catalogue: none may be left in Chinese. */
const ENGLISH = [
  "Read again",
  "Reading PDOs",
  "Export",
  "DCF fragment",
  "snippet",
  "Map by purpose",
  "Choose the modes",
  "Operating modes",
  "Profile velocity",
  "Profile torque",
  "Homing",
  "Interpolated",
  "Recommend mapping",
  "Edit current mapping",
  "Receive PDOs",
  "Transmit PDOs",
  "commands the drive",
  "what the drive sends",
  "Not valid",
  "not valid",
  "nothing mapped",
  "Show them",
  "Valid",
  "Transmission",
  "transmission",
  "Inhibit",
  "inhibit",
  "Event timer",
  "event timer",
  "SYNC start",
  "every",
  "synchronous",
  "acyclic",
  "(type",
  " bits",
  " bit)",
  "bit ·",
  " of 64",
  "bytes sent",
  "Byte ",
  "free",
  "frame",
  "Bus load",
  "SYNC every",
  "no SYNC",
  "Master cycle",
  "Warn above",
  "The bus would be",
  "All nodes",
  "Total bus load",
  "Node ",
  "How node",
  "Frames",
  "Bits / frame",
  "Load",
  "Counted as",
  "note on how",
  "notes on how",
  "Live check",
  "Start the node",
  "Start node",
  "watching",
  "Received PDOs",
  "Rate",
  "Values",
  "Sent by",
  "its TPDOs",
  "its RPDOs",
  "None seen",
  "No TPDO",
  "none yet",
  "The mapping is synchronous",
  "Produce SYNC",
  "SYNC produced",
  "Draft",
  "draft",
  "changed",
  "differ",
  "Same as the device",
  "Validate",
  "Apply",
  "Discard",
  "problem",
  "Checked",
  "On the device now",
  "Changes",
  "mapping",
  "made valid",
  "new PDO",
  "recommended for",
  "(edited)",
  "from the device",
  "fixed by the drive",
  "CAN identifier",
  "Move ",
  "Remove",
  "Add an object",
  "Find an object",
  "Objects for",
  "mapped objects",
  "No PDO-mappable",
  "narrow the search",
  "will get",
  "If a step fails",
  "Cancel",
  "is operational",
  "last check",
  "Not validated",
  "SYNC comes from",
  "Close",
  "Applied",
  "Read back",
  "Dismiss",
  "Not applied",
  "Each problem",
  "Apply failed",
  "Step",
  "Answer",
  "Device",
  "Restored",
  "Not restored",
  "is not PDO-mappable",
  "needs",
  "whole bytes",
  "read-only",
  "write-only",
  "already maps",
  "fixes the CAN id",
  "pre-defined",
  "Download",
];

/** What the server sent the page: object names, rules, load notes, live values. */
const SERVER: string[] = (
  [
    RULES.procedure,
    ...LOAD.notes,
    ...LOAD.nodes.flatMap((n) => n.pdos.map((p) => p.basis)),
    LIVE.drive_page,
    ...LIVE.pdos.flatMap((p) =>
      p.values.flatMap((v) => [v.name ?? "", v.text ?? "", "display" in v ? v.display : ""]),
    ),
    ...TREE.objects.flatMap((o) => [o.name, ...o.subs.map((s) => s.name)]),
  ] as (string | null | undefined)[]
)
  .filter((s): s is string => Boolean(s))
  .sort((a, b) => b.length - a.length); // a longer text before the shorter one inside it

/** The page's English texts found in what it shows, the server's texts taken out. */
function englishLeft(container: HTMLElement, serverTexts: readonly string[] = []): string[] {
  const text = [...serverTexts, ...SERVER].reduce(
    (rest, s) => rest.split(s).join(""),
    pageWords(container),
  );
  return ENGLISH.filter((english) => text.includes(english));
}

const QUIET = {
  producing: false,
  period_us: null,
  heard: false,
  heard_frames: 0,
  heard_period_us: null,
  source: null,
};

function render(routes: Record<string, Handler | object> = {}): HTMLElement {
  stubFetch({
    "GET /api/nodes/1/pdos": DEVICE,
    "GET /api/nodes/1/od": TREE,
    "GET /api/bus-load": (request: Request) => loadFor(request),
    "GET /api/sync": { producing: false, period_us: null },
    "GET /api/nodes/1/pdos/rules": RULES,
    "GET /api/nodes/1/pdos/recommended": { pdos: RECOMMENDED },
    ...routes,
  });
  const store = new LiveStore();
  store.upsertInfo(INFO);
  return renderPage(<PdoPage node={1} />, "/nodes/1/pdos", store).container;
}

async function recommend(): Promise<HTMLElement> {
  await userEvent.click(await screen.findByRole("button", { name: "推荐映射" }));
  return screen.findByRole("region", { name: "TPDO1 草稿" });
}

describe("PdoPage in zh-CN", () => {
  it("shows the device's PDOs, their frames and the bus load in Chinese", async () => {
    const container = render();
    const tpdo = within(await screen.findByRole("region", { name: "TPDO1" }));
    expect(document.documentElement.lang).toBe("zh-CN");
    expect(
      [...container.querySelectorAll("[data-testid=pdo-tpdo1] .pdo-facts dt")].map(
        (dt) => dt.textContent,
      ),
    ).toEqual(["COB-ID", "传输方式", "禁止时间", "事件定时器", "SYNC 起始值"]);
    expect(tpdo.getByText("每 5 个 SYNC")).toBeTruthy();
    expect(tpdo.getByText("（传输类型 5）")).toBeTruthy();
    expect(tpdo.getByText("有效")).toBeTruthy();
    const frame = tpdo.getByRole("list", { name: "TPDO1 报文" });
    expect(
      within(frame)
        .getAllByRole("listitem")
        .map((b) => b.getAttribute("aria-label")),
    ).toEqual(["Statusword（6041h:00，16 位）", "2FFFh:03（2FFFh:03，8 位）"]);
    expect(tpdo.getByText("已用 24 / 64 位 · 发送 3 字节")).toBeTruthy();
    expect(tpdo.getByText("空闲 40 位")).toBeTruthy();
    expect(screen.getByRole("heading", { name: "接收 PDO（RPDO）" })).toBeTruthy();
    expect(screen.getByRole("heading", { name: "发送 PDO（TPDO）" })).toBeTruthy();
    expect(screen.getByText(/^无效且未映射：RPDO2。/)).toBeTruthy();
    expect(screen.getAllByRole("button", { name: "显示" })).toHaveLength(2);

    for (const name of [
      "重新读取",
      "DCF 片段",
      "python-canopen 代码片段",
      "推荐映射",
      "编辑当前映射",
      "启动节点并监视 PDO",
      "产生 SYNC",
    ]) {
      expect(screen.getByRole("button", { name })).toBeTruthy();
    }
    expect(screen.getByRole("heading", { name: "按用途映射" })).toBeTruthy();
    expect(screen.getByRole("group", { name: "操作模式" })).toBeTruthy();
    expect(screen.getByLabelText("轮廓位置模式 (PP)")).toBeTruthy();
    expect(screen.getByLabelText("插补位置模式 (IP)")).toBeTruthy();
    expect(screen.getByRole("heading", { name: "实时检查" })).toBeTruthy();
    expect(screen.getByText("映射为同步方式，但 SYNC 未开启：")).toBeTruthy();

    const load = within(screen.getByTestId("bus-load"));
    expect(load.getByRole("heading", { name: "当前总线负载" })).toBeTruthy();
    expect(load.getByText(/· SYNC 周期 1 ms$/)).toBeTruthy();
    expect(load.getByLabelText("主站周期").getAttribute("title")).toBe(
      "没有 SYNC 时，假定主站发送每个事件驱动 RPDO 的周期",
    );
    expect(load.getByLabelText("警告阈值")).toBeTruthy();
    expect(load.getByRole("alert").textContent).toBe(
      "总线负载将达到 80 %，超过 70 %：报文可能被延迟。请降低 SYNC 频率、增大禁止时间或减少 PDO 映射。",
    );
    expect(load.getByRole("meter", { name: "总线总负载" })).toBeTruthy();
    expect(load.getByRole("meter", { name: "节点 1 负载" })).toBeTruthy();
    expect(load.getByText("节点 1 的 PDO 负载计算方式")).toBeTruthy();
    expect(
      load
        .getAllByRole("columnheader")
        .slice(0, 6)
        .map((th) => th.textContent),
    ).toEqual(["PDO", "COB-ID", "帧率", "位/帧", "负载", "计算依据"]);
    expect(load.getByText("关于负载估算的 1 条说明")).toBeTruthy();

    expect(englishLeft(container)).toEqual([]);
    expect(container.textContent).not.toMatch(/\bpdo\.[a-z]/);
  });

  it("drafts, edits, validates and applies a mapping in Chinese", async () => {
    const readBack = DEVICE.map(
      (p) => RECOMMENDED.find((r) => r.kind === p.kind && r.number === p.number) ?? p,
    );
    const problem = "TPDO1 is synchronous (every SYNC) but the drive refuses it";
    const container = render({
      "POST /api/nodes/1/pdos/validate": (request: Request): Validation => ({
        ok: false,
        problems: [{ kind: "tpdo", number: 1, message: problem, index: 0x1800, subindex: 2 }],
        warnings: [],
        sync: { ...QUIET, producing: true, period_us: 1000 },
        bus_load: loadFor(request),
      }),
      "PUT /api/nodes/1/pdos": readBack,
    });
    const tpdo = within(await recommend());
    const draft = within(screen.getByRole("region", { name: "草稿" }));
    expect(draft.getByRole("heading", { name: "草稿" })).toBeTruthy();
    expect(draft.getByText("为 PP 推荐")).toBeTruthy();
    expect(draft.getByText("2 个 PDO 与设备不同：RPDO1、TPDO1。")).toBeTruthy();
    expect(draft.getByRole("button", { name: "放弃草稿" })).toBeTruthy();
    expect(tpdo.getByText("草稿：已更改")).toBeTruthy();
    expect(tpdo.getByText("设备当前配置：")).toBeTruthy();
    expect(tpdo.getByRole("list", { name: "设备上的 TPDO1 报文" })).toBeTruthy();
    expect(container.querySelector("[data-testid=pdo-tpdo1] .pdo-changes")?.textContent).toBe(
      "更改： 传输类型 5 → 1（每个 SYNC）；禁止时间 2.5 → 0 ms；事件定时器 100 → 0 ms；映射 → Statusword、Position actual value",
    );

    // the communication parameter's fields and the COB-ID the drive fixes
    expect(tpdo.getByLabelText("有效")).toBeTruthy();
    const cobId = tpdo.getByLabelText("TPDO1 COB-ID");
    expect(cobId.getAttribute("title")).toBe(
      "该驱动器将 PDO 1–4 的 CAN ID 固定为预定义连接集的值，只能更改有效位。",
    );
    expect(tpdo.getByText("由驱动器固定")).toBeTruthy();
    for (const name of [
      "TPDO1 传输类型",
      "TPDO1 禁止时间 ms",
      "TPDO1 事件定时器 ms",
      "TPDO1 SYNC 起始值",
    ]) {
      expect(tpdo.getByLabelText(name)).toBeTruthy();
    }

    // the mapping editor and the picker; an object that does not fit is refused in Chinese
    const entries = within(tpdo.getByRole("list", { name: "TPDO1 映射对象" }));
    expect(entries.getByRole("button", { name: "将 Statusword 下移" })).toBeTruthy();
    expect(entries.getByRole("button", { name: "将 Position actual value 上移" })).toBeTruthy();
    expect(entries.getByRole("button", { name: "从 TPDO1 中移除 Statusword" }).textContent).toBe(
      "移除",
    );
    const rpdo = within(screen.getByRole("region", { name: "RPDO1 草稿" }));
    const find = rpdo.getByRole("searchbox", { name: "查找要映射到 RPDO1 的对象" });
    expect(find.getAttribute("placeholder")).toBe("添加对象：名称、6064 或 6064:00");
    await userEvent.type(find, "6064");
    const found = within(rpdo.getByRole("list", { name: "RPDO1 的可选对象" }));
    await userEvent.click(
      found.getByRole("button", { name: "添加 Position actual value 6064h:00" }),
    );
    expect(rpdo.getByRole("alert").textContent).toBe(
      "RPDO 向驱动器写入数据，但 Position actual value (6064h:00) 为只读。",
    );
    await userEvent.clear(find);
    await userEvent.type(find, "zzzz");
    expect(rpdo.getByText("没有匹配的可 PDO 映射对象。")).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);

    // a hand edit marks the draft; the check's problem sits at its field
    const type = tpdo.getByLabelText("TPDO1 传输类型");
    await userEvent.clear(type);
    await userEvent.type(type, "254");
    expect(draft.getByText("为 PP 推荐（已编辑）")).toBeTruthy();
    expect(tpdo.getByText("变化时发送 + 事件定时器（制造商自定义事件）")).toBeTruthy();
    await userEvent.click(draft.getByRole("button", { name: "校验" }));
    expect(await draft.findByText("1 个问题")).toBeTruthy();
    expect(screen.getByRole("heading", { name: "应用草稿后的总线负载" })).toBeTruthy();
    const fields = within(tpdo.getByRole("list", { name: "TPDO1 通信参数的问题" }));
    expect(fields.getByText("传输类型：")).toBeTruthy();
    expect(englishLeft(container, [problem])).toEqual([]);

    // the confirmation says what changes and how the node takes it
    await userEvent.click(draft.getByRole("button", { name: "应用…" }));
    const dialog = within(screen.getByRole("dialog", { name: "将 PDO 映射应用到节点 1" }));
    expect(dialog.getByText("节点 1 将采用以下 PDO 设置：")).toBeTruthy();
    expect(dialog.getByText("节点 1 接受新映射的方式：").parentElement?.textContent).toBe(
      `节点 1 接受新映射的方式： ${RULES.procedure}. 任一步骤失败时，将写回原来的设置。`,
    );
    expect(dialog.getByText("上次校验发现 1 个问题，驱动器很可能会拒绝。")).toBeTruthy();
    expect(dialog.getByRole("button", { name: "关闭对话框" })).toBeTruthy();
    expect(dialog.getByRole("button", { name: "取消" })).toBeTruthy();
    expect(englishLeft(container, [problem])).toEqual([]);
    await userEvent.click(dialog.getByRole("button", { name: "应用" }));

    const result = within(await screen.findByRole("status", { name: "应用结果" }));
    expect(result.getByRole("heading", { name: "已应用" })).toBeTruthy();
    expect(
      result.getByText("已从设备回读：4 个 PDO，其中 2 个有效。下方的 PDO 即设备当前的配置。"),
    ).toBeTruthy();
    expect(result.getByRole("button", { name: "关闭" })).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);
    expect(container.textContent).not.toMatch(/\bpdo\.[a-z]/);
  });

  it("says which step failed and whether the device was restored, in Chinese", async () => {
    const step = "write 1A00h:02 (TPDO1 mapping entry 2)";
    const answer = "Object cannot be mapped to the PDO";
    const container = render({
      "PUT /api/nodes/1/pdos": json(
        {
          error: "pdo_apply_failed",
          step,
          abort_code: "0x06040041",
          message: answer,
          restored: false,
        },
        409,
      ),
    });
    await recommend();
    await userEvent.click(screen.getByRole("button", { name: "应用…" }));
    expect(screen.getByText("尚未校验。")).toBeTruthy();
    await userEvent.click(within(screen.getByRole("dialog")).getByRole("button", { name: "应用" }));
    const result = within(await screen.findByRole("alert", { name: "应用结果" }));
    expect(result.getByRole("heading", { name: "应用失败" })).toBeTruthy();
    expect(result.getAllByRole("term").map((dt) => dt.textContent)).toEqual([
      "步骤",
      "应答",
      "设备",
    ]);
    expect(
      result.getByText("未恢复：PDO 可能只配置了一部分。启动节点前请重新读取并检查。"),
    ).toBeTruthy();
    expect(englishLeft(container, [step, answer])).toEqual([]);
  });

  it("warns of a synchronous draft without SYNC in Chinese", async () => {
    const warnings = ["RPDO1 is synchronous", "TPDO1 is synchronous"];
    const container = render({
      "POST /api/nodes/1/pdos/validate": (request: Request): Validation => ({
        ok: false,
        problems: [],
        warnings: warnings.map((message, i) => ({
          kind: i === 0 ? "rpdo" : "tpdo",
          number: 1,
          message,
          index: null,
          subindex: null,
        })),
        sync: QUIET,
        bus_load: loadFor(request),
      }),
    });
    await recommend();
    await userEvent.click(screen.getByRole("button", { name: "校验" }));
    expect(await screen.findByText("总线上没有 SYNC")).toBeTruthy();
    const group = within(screen.getByRole("group", { name: "同步 PDO 的 SYNC 来源" }));
    expect(group.getByRole("alert").textContent).toBe(
      "RPDO1、TPDO1 为同步 PDO，但总线上既没有产生也没有收到 SYNC：收到 SYNC 后才会动作。 要写入，请启动 SYNC 生产者，或注明 SYNC 由机器的控制器提供。",
    );
    expect(group.getByLabelText("SYNC 由机器的控制器（PLC）提供")).toBeTruthy();
    await userEvent.click(screen.getByRole("button", { name: "应用…" }));
    expect(
      screen.getByText(
        "总线上既没有产生也没有收到 SYNC：请启动 SYNC 生产者，或注明 SYNC 由机器的控制器提供。",
      ),
    ).toBeTruthy();
    expect(englishLeft(container, warnings)).toEqual([]);
  });

  it("starts the node and watches its PDOs in Chinese", async () => {
    const container = render({
      "GET /api/bus-load": LOAD,
      "PUT /api/sync": { producing: true, period_us: 10_000 },
      "POST /api/nodes/1/nmt": { ...INFO, nmt_state: "operational" },
      "POST /api/nodes/1/pdos/live": { ...LIVE, pdos: [] },
      "GET /api/nodes/1/pdos/live": LIVE,
      "DELETE /api/nodes/1/pdos/live": { ...LIVE, active: false },
    });
    await userEvent.click(await screen.findByRole("button", { name: "产生 SYNC" }));
    expect(await screen.findByText("正在产生 SYNC，周期 10 ms")).toBeTruthy();
    await userEvent.click(screen.getByRole("button", { name: "启动节点并监视 PDO" }));
    const table = within(await screen.findByRole("table", { name: "收到的 PDO" }));
    expect(await table.findByText("100/s")).toBeTruthy();
    expect(
      table
        .getAllByRole("columnheader")
        .slice(0, 5)
        .map((th) => th.textContent),
    ).toEqual(["COB-ID", "PDO", "帧数", "速率", "值"]);
    expect(
      table
        .getAllByRole("rowgroup")
        .map((g) => g.getAttribute("aria-label"))
        .slice(1),
    ).toEqual(["节点 1 发送", "主站发送"]);
    expect(table.getByText("节点 1 发送", { exact: false }).textContent).toBe(
      "节点 1 发送 （其 TPDO）",
    );
    expect(table.getByText(/^主站发送给节点 1/).textContent).toBe("主站发送给节点 1 （其 RPDO）");
    expect(table.getByText("未收到主站发送的：RPDO1 (0x201)、RPDO2 (0x301)。")).toBeTruthy();
    expect(table.getByText("Statusword").nextElementSibling?.getAttribute("title")).toBe(
      "6041h:00 字节：50 02 = 592",
    );
    expect(screen.getByText("监视中")).toBeTruthy();
    expect(screen.getByRole("button", { name: "停止监视" })).toBeTruthy();
    expect(englishLeft(container, ["100/s"])).toEqual([]);
  });

  it("shows an export in Chinese", async () => {
    const container = render({
      "GET /api/nodes/1/pdos/export": () =>
        new Response("[1A00sub0]\nParameterValue=0x02\n", { status: 200 }),
    });
    await userEvent.click(await screen.findByRole("button", { name: "DCF 片段" }));
    const dialog = within(await screen.findByRole("dialog", { name: "节点 1：DCF 片段" }));
    expect(dialog.getByLabelText("DCF 片段")).toBeTruthy();
    expect(dialog.getByRole("button", { name: "下载 node1-pdos.dcf" })).toBeTruthy();
    expect(dialog.getByRole("button", { name: "关闭" })).toBeTruthy();
    expect(screen.getByText("导出：")).toBeTruthy();
    expect(englishLeft(container, ["[1A00sub0]\nParameterValue=0x02\n", "pdos.dcf"])).toEqual([]);
  });
});
