// The Commission tab in Simplified Chinese: headings, labels, buttons, warnings and tables from
// the zh-CN catalogue; step titles, reasons, evidence and error messages stay as the server sends
// them; none of the page's English texts left, no bare catalogue key anywhere.
import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import { json, stubFetch } from "../../test/fetchStub";
import {
  identityDone,
  record,
  stopTestDone,
  storeVerifyLost,
} from "../../test/fixtures/commission";
import { inChinese } from "../../test/inChinese";
import { pageWords } from "../../test/pageWords";
import { renderPage, sessionAs } from "../../test/render";
import { CommissionPage } from "./CommissionPage";
import { serve } from "./fixtures";

inChinese();

/** The step titles in Chinese (the server sends them in English). */
const TITLES = [
  "识别",
  "通信",
  "参数",
  "PDO 映射",
  "限值",
  "停机测试",
  "试运行",
  "回零",
  "保存并校验",
];

/** The page's English texts, replaced by the catalogue: none may be left in Chinese. */
const ENGLISH = [
  "Identity",
  "Communication",
  "PDO mapping",
  "Homing",
  "Store and verify",
  "Loading the records",
  "Commissioning steps",
  "Start commissioning",
  "A record walks",
  "operating modes",
  "Reading the supported modes",
  "Modes",
  "the drive supports",
  "none",
  "Title",
  "(optional)",
  "e.g.",
  "Start record",
  "Cancel",
  "Pick at least one mode",
  "Profile position",
  "Profile velocity",
  "Profile torque",
  "Interpolated position",
  "Record",
  "steps done or skipped",
  "Progress",
  "New record",
  "Drive",
  "(1018h)",
  "vendor 0x",
  "product 0x",
  "SN 0x",
  "Started",
  "Choose a record",
  "Hand-over report",
  "Report (HTML)",
  "Bundle (zip)",
  "untitled",
  "In progress",
  "To do",
  "Done",
  "Skipped",
  "Failed",
  "Step ",
  "by local",
  "Reason",
  "Values lost",
  "Not kept over the reset",
  "expected",
  "now ",
  "Evidence",
  "Run ",
  "Run again",
  "Sign off",
  "Skip",
  "Running",
  "Or map the PDOs",
  "Or home the axis",
  "sign this step off",
  "Why is",
  "(required)",
  "Give a reason",
  "The axis will move",
  "Keep clear",
  "Quick stop all",
  "Drive page",
  "Network page",
  "ServoDesk jogs",
  "ServoDesk enables",
  "Speed",
  "at most half",
  "PP move",
  "Stop test speed",
  "Test move distance",
  "relative, at",
  "Apply the manuals",
  "writes the PDOs",
  "engineer role",
  "Method",
  "As set in the drive",
  "holds the axis",
  "another client",
  "Values read",
  "Writes since",
  "Objects changed",
  "Read back after",
  "Heartbeat consumers",
  "Jogs",
  "Figures of",
  "Figure",
  "Value",
  "Unit",
];

/** The page's English texts found in what it shows, the server's texts taken out: step titles,
 * reasons, messages, and the evidence's own keys and values (lines and table bodies). */
function englishLeft(container: HTMLElement, serverTexts: readonly string[] = []): string[] {
  const server = ["CiA 402 controller (Nanotec style)", "C5-E-SIM", "Axis X", ...serverTexts];
  const text = server.reduce(
    (rest, s) => rest.split(s).join(""),
    pageWords(container, [".evidence-lines", ".evidence-table tbody", ".figures-table tbody"]),
  );
  return ENGLISH.filter((english) => text.includes(english));
}

const step = (index: number, title: string): HTMLElement =>
  screen.getByRole("listitem", { name: `第 ${index} 步：${title}` });

describe("CommissionPage in zh-CN", () => {
  it("starts a record in Chinese", async () => {
    stubFetch({
      "GET /api/commissioning": [],
      "GET /api/nodes/3/drive": { node: 3, supported_modes: ["pp", "pv", "pt", "hm", "ip"] },
    });
    const { container } = renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    expect(await screen.findByRole("heading", { name: "开始调试节点 3" })).toBeTruthy();
    expect(document.documentElement.lang).toBe("zh-CN");
    const pp = await screen.findByRole<HTMLInputElement>("checkbox", { name: "PP 轮廓位置" });
    expect(pp.checked).toBe(true);
    expect(screen.getByRole("checkbox", { name: "HM 回零" })).toBeTruthy();
    expect(screen.getByText("模式（驱动器支持：PP, PV, PT, HM, IP）")).toBeTruthy();
    const title = screen.getByRole("textbox", { name: "标题 （可选）" });
    expect(title.getAttribute("placeholder")).toBe("例如：X 轴，4711 号机床");
    expect(screen.getByRole("button", { name: "创建记录" })).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);

    await userEvent.click(pp);
    await userEvent.click(screen.getByRole("checkbox", { name: "PV 轮廓速度" }));
    expect(screen.getByText("请至少选择一种模式。")).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);
    expect(container.textContent).not.toMatch(/\bcommission\.[a-z]/);
  });

  it("shows the record, its steps and their evidence in Chinese", async () => {
    const server = [
      "not kept over the reset: 2006:08 PA-103: expected 5000, now 6000",
      "absolute encoder, no homing",
      "Current position",
      "Device type",
      "Vendor-ID",
    ];
    serve(
      record({}, { homing: { status: "skipped", reason: "absolute encoder, no homing" } }),
      {
        identity: () => identityDone,
        stop_test: () => stopTestDone,
        store_verify: () => storeVerifyLost,
        pdo: () => ({ ...record().steps[3], status: "done", evidence: { applied: true } }),
      },
      {
        "GET /api/nodes/3/drive/homing-methods": () => [
          { method: 35, name: "Current position", description: "", path: [] },
        ],
      },
    );
    const { container } = renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    expect(await screen.findByRole("heading", { name: "调试记录 #1：Axis X" })).toBeTruthy();
    expect(screen.getByText("进行中")).toBeTruthy();
    expect(screen.getByLabelText("进度").textContent).toBe("已完成或跳过 1/9 步");
    expect(screen.getByRole("button", { name: "新建记录…" })).toBeTruthy();
    expect(screen.getByText("交接报告")).toBeTruthy();
    expect(screen.getByRole("link", { name: "报告（HTML）" })).toBeTruthy();
    expect(screen.getByRole("link", { name: "资料包（zip）" })).toBeTruthy();
    expect(screen.getByText("设备标识（1018h）")).toBeTruthy();
    expect(screen.getByText(/^厂商 0x0000026C · 产品 0x000000C5 · 版本 0x00000001/)).toBeTruthy();
    const steps = within(screen.getByRole("list", { name: "调试步骤" }));
    expect(steps.getAllByRole("listitem").map((li) => li.getAttribute("aria-label"))).toEqual(
      TITLES.map((title, i) => `第 ${i + 1} 步：${title}`),
    );

    // the skipped step: the page's word before the server's reason
    const homing = within(step(8, "回零"));
    expect(homing.getByText("原因：absolute encoder, no homing")).toBeTruthy();
    expect(homing.getByRole("note", { name: "轴将会运动" }).textContent).toContain(
      "ServoDesk 使能驱动器并执行回零",
    );
    expect(homing.getByRole("link", { name: "驱动器页面" })).toBeTruthy();
    expect(homing.getByRole("link", { name: "或在驱动器页面使用回零向导完成回零" })).toBeTruthy();
    const method = homing.getByRole("combobox", { name: "回零方式" });
    expect(within(method).getByRole("option", { name: "按驱动器中的设置（6098h）" })).toBeTruthy();
    await homing.findByRole("option", { name: "35: Current position" });

    // the pdo step: the choice, and the manual way on the PDOs page
    const pdo = within(step(4, "PDO 映射"));
    expect(
      pdo.getByRole("checkbox", { name: "先为本记录的模式应用手册推荐的 PDO 映射" }),
    ).toBeTruthy();
    expect(pdo.getByText("（会写入 PDO；不勾选时，此步骤按现有映射进行检查）")).toBeTruthy();
    expect(pdo.getByRole("link", { name: "或在 PDO 页面手动配置 PDO 映射" })).toBeTruthy();
    expect(pdo.getByRole("button", { name: "签字确认 PDO 映射" })).toBeTruthy();
    expect(pdo.getByRole("button", { name: "跳过 PDO 映射…" })).toBeTruthy();

    const stop = within(step(6, "停机测试"));
    expect(stop.getByRole("spinbutton", { name: "停止测试速度（rpm）" })).toBeTruthy();
    expect(stop.getByText("（不超过速度限值的一半）")).toBeTruthy();
    const move = within(step(7, "试运行"));
    const distance = move.getByRole("spinbutton", { name: "试运行距离（rev）" });
    expect(englishLeft(container, server)).toEqual([]);

    // a refused input, in Chinese, before anything is sent
    await userEvent.clear(distance);
    await userEvent.type(distance, "0");
    await userEvent.click(move.getByRole("button", { name: "运行 试运行" }));
    expect(move.getByRole("alert").textContent).toBe(
      "距离必须在 −100 到 100 rev 之间，且不能为 0。",
    );

    // identity: the values read, with the page's headings and the server's values
    await userEvent.click(screen.getByRole("button", { name: "运行 识别" }));
    const identity = within(step(1, "识别"));
    expect(await identity.findByText("已完成")).toBeTruthy();
    expect(identity.getByText(/^操作人：local，/)).toBeTruthy();
    expect(identity.getByRole("button", { name: "重新运行 识别" }).textContent).toBe("重新运行");
    const values = identity.getByRole("table", { name: "读取的值（识别）" });
    expect(within(values).getByText("读取的值")).toBeTruthy();
    expect(
      within(values)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["对象", "名称", "值"]);
    expect(within(values).getByText("Vendor-ID")).toBeTruthy();
    expect(identity.getByText("证据")).toBeTruthy();

    // the stop test's figures
    await userEvent.click(stop.getByRole("button", { name: "运行 停机测试" }));
    const figures = await stop.findByRole("table", { name: "停机测试 的测量结果" });
    expect(
      within(figures)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["测量项", "数值", "单位"]);

    // a boolean in the evidence reads 是/否
    await userEvent.click(pdo.getByRole("button", { name: "运行 PDO 映射" }));
    const applied = await pdo.findByText("applied");
    expect(applied.nextElementSibling?.textContent).toBe("是");

    // store_verify lost a value: the page's lines in Chinese, the server's reason as sent
    const verify = within(step(9, "保存并校验"));
    await userEvent.click(verify.getByRole("button", { name: "运行 保存并校验" }));
    expect(await verify.findByText("失败")).toBeTruthy();
    expect(
      verify.getByText("失败：not kept over the reset: 2006:08 PA-103: expected 5000, now 6000"),
    ).toBeTruthy();
    const lost = verify.getByRole("alert", { name: "复位后丢失的值" });
    expect(within(lost).getByText("复位后未保留的值：")).toBeTruthy();
    expect(within(lost).getByText("2006:08 PA-103：应为 5000，实际为 6000")).toBeTruthy();
    const table = verify.getByRole("table", { name: "复位后未保留（保存并校验）" });
    expect(
      within(table)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["对象", "名称", "期望值", "当前值", "原值"]);

    // skipping asks for a reason
    await userEvent.click(screen.getByRole("button", { name: "跳过 限值…" }));
    const limits = within(step(5, "限值"));
    const form = limits.getByRole("form", { name: "跳过 限值" });
    expect(within(form).getByText(/^为什么跳过“限值”？/)).toBeTruthy();
    expect(within(form).getByRole("textbox", { name: "跳过 限值 的原因" })).toBeTruthy();
    expect(
      within(form).getByRole<HTMLButtonElement>("button", { name: "跳过此步骤" }).disabled,
    ).toBe(true);
    expect(within(form).getByText("请填写跳过的原因。")).toBeTruthy();
    expect(within(form).getByRole("button", { name: "取消" })).toBeTruthy();

    expect(englishLeft(container, [...server, "applied"])).toEqual([]);
    // a key the catalogue missed would show as "commission.…"
    expect(container.textContent).not.toMatch(/\bcommission\.[a-z]/);
  });

  it("says who holds the axis and what runs, in Chinese", async () => {
    const message = "node 3 is controlled by Chrome tab 8933: take over control first";
    serve(record(), {
      test_move: () =>
        json(
          {
            error: "held_by_other",
            message,
            node: 3,
            holder: { client_id: "tab-8933", name: "Chrome tab 8933", since: 1_764_000_000 },
          },
          409,
        ),
      homing: () => new Promise(() => undefined),
    });
    const { container } = renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    await userEvent.click(await screen.findByRole("button", { name: "运行 试运行" }));
    const move = within(step(7, "试运行"));
    expect(await move.findByText(message)).toBeTruthy();
    expect(move.getByText(/^Chrome tab 8933 正在控制该轴：/)).toBeTruthy();

    await userEvent.click(screen.getByRole("button", { name: "运行 回零" }));
    const homing = within(step(8, "回零"));
    expect(await homing.findByText("正在回零：等待驱动器报告回零完成…")).toBeTruthy();
    expect(homing.getByRole("status", { name: "正在运行 回零" })).toBeTruthy();
    expect(englishLeft(container, [message, "Chrome tab 8933"])).toEqual([]);
  });

  it("offers older records and says why a viewer may not act, in Chinese", async () => {
    const newest = record({ id: 2, title: "", status: "failed" });
    const older = record({ id: 1, title: "first", status: "done" });
    stubFetch({
      "GET /api/commissioning": [newest, older],
      "GET /api/commissioning/2": newest,
      "GET /api/commissioning/1": older,
      "GET /api/nodes/3/drive/homing-methods": [],
    });
    const { container } = renderPage(
      <CommissionPage node={3} />,
      "/nodes/3/commission",
      undefined,
      sessionAs("viewer"),
    );

    expect(await screen.findByRole("heading", { name: "调试记录 #2" })).toBeTruthy();
    const chooser = screen.getByRole("combobox", { name: "选择调试记录" });
    const options = within(chooser)
      .getAllByRole("option")
      .map((o) => o.textContent);
    expect(options[0]).toMatch(/^#2 未命名 — .*（失败）$/);
    expect(options[1]).toMatch(/^#1 first — .*（已完成）$/);
    expect(screen.getByRole("button", { name: "新建记录…" }).getAttribute("title")).toContain(
      "才能创建调试记录",
    );
    const identity = within(step(1, "识别"));
    expect(identity.getByRole("button", { name: "运行 识别" }).getAttribute("title")).toContain(
      "才能运行“识别”步骤",
    );
    expect(identity.getByRole("button", { name: "签字确认 识别" }).getAttribute("title")).toContain(
      "才能签字确认步骤",
    );
    expect(identity.getByRole("button", { name: "跳过 识别…" }).getAttribute("title")).toContain(
      "才能跳过步骤",
    );
    expect(within(step(4, "PDO 映射")).getByText(/^（写入 PDO 需要工程师角色/)).toBeTruthy();
    expect(englishLeft(container, ["first"])).toEqual([]);
    // the report in the page's language
    expect(screen.getByRole("link", { name: "报告（HTML）" }).getAttribute("href")).toBe(
      "/api/commissioning/2/report?format=html&lang=zh-CN",
    );
    expect(screen.getByRole("link", { name: "PDF" }).getAttribute("href")).toBe(
      "/api/commissioning/2/report?format=pdf&lang=zh-CN",
    );
    expect(screen.getByRole("link", { name: "资料包（zip）" }).getAttribute("href")).toBe(
      "/api/commissioning/2/report?format=zip&lang=zh-CN",
    );
  });
});
