// The Parameters page in Simplified Chinese: headings, columns, buttons, dialogs and wizards from
// the zh-CN catalogue; parameter names and labels stay as the drive catalogue sends them; none of
// the page's English texts left, no bare catalogue key anywhere.
import { render, screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { MemoryRouter } from "react-router";
import { describe, expect, it } from "vitest";

import type { CompareResult, Param } from "../../api/types";
import { LiveProvider } from "../../live/LiveProvider";
import { LiveStore } from "../../live/store";
import { stubFetch } from "../../test/fetchStub";
import { inChinese } from "../../test/inChinese";
import { pageWords } from "../../test/pageWords";
import { renderPage, sessionAs } from "../../test/render";
import { PA103, PA106 } from "./fixtures";
import { ParamsPage } from "./ParamsPage";

inChinese();

const PA200: Param = { ...PA103, name: "PA-200", takes_effect: "after_store_and_reset" };

const COMPARED: CompareResult = {
  rows: [
    {
      name: "Heartbeat",
      index: 0x1017,
      subindex: 0,
      unit: "ms",
      device: 0,
      device_text: "0",
      file: 100,
      file_text: "100",
      default: 0,
      default_text: "0",
      differs_from_file: true,
      differs_from_default: false,
    },
  ],
  read_only: [],
  identity: { matches: true, file: "vendor 0x26C", device: "vendor 0x26C", checked: true },
  confirm: [],
};

/** The page's English texts, replaced by the catalogue: none may be left in Chinese. */
const ENGLISH = [
  "Parameters",
  "Read again",
  "Reading parameters",
  "Store parameters",
  "Store",
  "Restore defaults",
  "Change node ID",
  "Change bitrate",
  "Takes effect",
  "Range",
  "Default",
  "Value",
  "Unit",
  "Label",
  "immediately",
  "after reset",
  "after store + reset",
  "pending until reset",
  "Written since the drive last booted",
  "Write",
  "Parameter set",
  "Save DCF",
  "Load DCF",
  "Compare",
  "Cancel",
  "Close",
  'Writes "save"',
  'Writes "load"',
  "non-volatile",
  "factory defaults",
  "is outside",
  "whole number",
  "not in list",
  "Only differences",
  "entries differ",
  "No differences",
  "EDS default",
  "Device now",
  "From the file",
  "Values that would change",
  "would change",
  "Nothing has been written",
  "The server will",
  "New node ID",
  "New bitrate",
  "boot-up message at the new id",
  "has to follow",
  "(now)",
  "talks only at",
  "Node ",
  "node ",
  "No parameter catalogue",
  "generic profile",
  "Object dictionary tab",
  "Written ",
  "skipped",
  "but check",
  "Restored defaults",
  "Reset node",
  "restored its default parameters",
  "reset node",
  "is now node",
];

/** The page's English texts found in what it shows, fixtures' server texts taken out. */
function englishLeft(container: HTMLElement, serverTexts: readonly string[] = []): string[] {
  const server = [
    "CAN bitrate",
    "Bitrate of the CAN interface",
    "Maximum speed",
    "250 kbit/s",
    "500 kbit/s",
    ...serverTexts,
  ];
  // the shared dialog frame's close button is not this page's
  const text = server.reduce(
    (rest, s) => rest.split(s).join(""),
    pageWords(container, ["[data-dialog-close]"]),
  );
  return ENGLISH.filter((english) => text.includes(english));
}

describe("ParamsPage in zh-CN", () => {
  it("shows the table, the parameter set and the row controls in Chinese", async () => {
    stubFetch({
      "GET /api/nodes/1/params": [PA106, PA103, PA200],
      "PUT /api/nodes/1/params/PA-106": {
        param: { ...PA106, value: 4, pending: true },
        message: "written",
        requires_reset: true,
        requires_store: true,
      },
    });
    const { container } = renderPage(<ParamsPage node={1} />, "/nodes/1/parameters");

    expect(await screen.findByRole("rowheader", { name: "PA-106" })).toBeTruthy();
    expect(document.documentElement.lang).toBe("zh-CN");
    expect(screen.getAllByRole("heading", { level: 2 }).map((h) => h.textContent)).toEqual([
      "参数",
      "参数集",
    ]);
    const table = screen.getAllByRole("table")[0] as HTMLElement;
    expect(
      within(table)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["参数号", "名称", "值", "单位", "范围", "默认值", "生效时机"]);
    for (const name of [
      "重新读取",
      "存储参数",
      "恢复出厂设置",
      "更改节点 ID…",
      "更改波特率…",
      "保存 DCF",
      "加载 DCF…",
      "比较…",
      "写入 PA-106",
      "写入 PA-103",
    ]) {
      expect(screen.getByRole("button", { name })).toBeTruthy();
    }
    expect(screen.getByLabelText("加载 DCF…")).toBeTruthy();
    expect(screen.getByText("复位后生效")).toBeTruthy();
    expect(screen.getByText("立即生效")).toBeTruthy();
    expect(screen.getByText("存储并复位后生效")).toBeTruthy();

    // a value out of range is refused in Chinese, before anything is sent
    const input = screen.getByLabelText("PA-103", { selector: "input" });
    await userEvent.clear(input);
    await userEvent.type(input, "7000");
    await userEvent.click(screen.getByRole("button", { name: "写入 PA-103" }));
    expect(screen.getByRole("alert").textContent).toBe("7000 超出范围 0…6000");
    await userEvent.clear(input);
    await userEvent.type(input, "x");
    await userEvent.click(screen.getByRole("button", { name: "写入 PA-103" }));
    expect(screen.getByRole("alert").textContent).toBe("请输入整数（0…6000）");

    // written, not in effect yet: the badge and its tooltip in Chinese; the server's word as sent
    await userEvent.selectOptions(screen.getByLabelText("PA-106", { selector: "select" }), "4");
    await userEvent.click(screen.getByRole("button", { name: "写入 PA-106" }));
    expect(await screen.findByText("PA-106: written")).toBeTruthy();
    const badge = screen.getByText("待复位生效");
    expect(badge.getAttribute("title")).toBe("自驱动器上次启动以来已写入：驱动器仍按原来的值运行");

    expect(englishLeft(container, ["written"])).toEqual([]);
    // a key the catalogue missed would show as "params.…"
    expect(container.textContent).not.toMatch(/\bparams\.[a-z]/);
  });

  it("says why a role may not write, store or load, in Chinese", async () => {
    stubFetch({ "GET /api/nodes/1/params": [PA103] });
    renderPage(
      <ParamsPage node={1} />,
      "/nodes/1/parameters",
      new LiveStore(),
      sessionAs("operator"),
    );
    await screen.findByRole("rowheader", { name: "PA-103" });
    expect(screen.getByRole("button", { name: "写入 PA-103" }).getAttribute("title")).toContain(
      "才能写入参数",
    );
    expect(screen.getByRole("button", { name: "存储参数" }).getAttribute("title")).toContain(
      "才能存储参数",
    );
    expect(screen.getByRole("button", { name: "加载 DCF…" }).getAttribute("title")).toContain(
      "才能将 DCF 加载到节点",
    );
  });

  it("asks before storing and restoring, then offers the reset, in Chinese", async () => {
    stubFetch({
      "GET /api/nodes/1/params": [PA103],
      "POST /api/nodes/1/restore-defaults": { node: 1, message: "restored" },
    });
    const { container } = renderPage(<ParamsPage node={1} />, "/nodes/1/parameters");
    await screen.findByRole("rowheader", { name: "PA-103" });

    await userEvent.click(screen.getByRole("button", { name: "存储参数" }));
    let dialog = within(screen.getByRole("dialog", { name: "存储参数" }));
    expect(dialog.getByText(/^向 1010h:01 写入“save”：节点 1 将当前参数/)).toBeTruthy();
    expect(dialog.getByRole("button", { name: "存储" })).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);
    await userEvent.click(dialog.getByRole("button", { name: "取消" }));

    await userEvent.click(screen.getByRole("button", { name: "恢复出厂设置" }));
    dialog = within(screen.getByRole("dialog", { name: "恢复出厂设置" }));
    expect(dialog.getByText(/^向 1011h:01 写入“load”：节点 1 用出厂默认值/)).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);
    await userEvent.click(dialog.getByRole("button", { name: "恢复出厂设置" }));

    const restored = await screen.findByRole("status", { name: "已恢复出厂设置" });
    expect(within(restored).getByText("节点 1 已恢复默认参数，复位节点后生效。")).toBeTruthy();
    await userEvent.click(within(restored).getByRole("button", { name: "立即复位节点 1" }));
    dialog = within(screen.getByRole("dialog", { name: "立即复位节点 1" }));
    expect(dialog.getByText(/^向节点 1 发送 NMT“复位节点”/)).toBeTruthy();
    expect(dialog.getByRole("button", { name: "复位节点" })).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);
  });

  it("walks the node-ID and bitrate wizards in Chinese", async () => {
    stubFetch({
      "GET /api/nodes/1/params": [PA103],
      "GET /api/nodes/1/node-id-options": { settable: true, note: "PA-105 sets the id" },
      "GET /api/nodes/1/bitrates": {
        settable: true,
        supported: [250_000, 500_000],
        current: 500_000,
        note: "PA-106 sets the bitrate",
      },
    });
    const store = new LiveStore();
    const { container } = renderPage(<ParamsPage node={1} />, "/nodes/1/parameters", store);
    await screen.findByRole("rowheader", { name: "PA-103" });
    const server = ["PA-105 sets the id", "PA-106 sets the bitrate"];

    await userEvent.click(screen.getByRole("button", { name: "更改节点 ID…" }));
    let dialog = within(await screen.findByRole("dialog", { name: "更改节点 1 的节点 ID" }));
    const id = await dialog.findByLabelText("新节点 ID（1–127）");
    expect(dialog.getByText("服务器将：")).toBeTruthy();
    expect(dialog.getByText("复位节点，")).toBeTruthy();
    expect(englishLeft(container, server)).toEqual([]);
    await userEvent.type(id, "200");
    await userEvent.click(dialog.getByRole("button", { name: "更改节点 ID" }));
    expect(dialog.getByRole("alert").textContent).toBe("节点 ID 范围为 1–127");
    await userEvent.clear(id);
    await userEvent.type(id, "1");
    await userEvent.click(dialog.getByRole("button", { name: "更改节点 ID" }));
    expect(dialog.getByRole("alert").textContent).toBe("该节点的 ID 已是 1");
    await userEvent.click(dialog.getByRole("button", { name: "取消" }));

    await userEvent.click(screen.getByRole("button", { name: "更改波特率…" }));
    dialog = within(await screen.findByRole("dialog", { name: "更改节点 1 的波特率" }));
    const select = await dialog.findByLabelText("新波特率");
    expect(
      within(select)
        .getAllByRole("option")
        .map((o) => o.textContent),
    ).toEqual(["250 kbit/s", "500 kbit/s（当前）"]);
    expect(dialog.getByText("服务器将写入驱动器的波特率参数、存储参数并复位节点。")).toBeTruthy();
    expect(dialog.getByText(/^此后节点 1 只以 250 kbit\/s 通信/)).toBeTruthy();
    expect(dialog.getByRole("button", { name: "更改波特率" })).toBeTruthy();
    expect(englishLeft(container, server)).toEqual([]);
  });

  it("compares and loads a DCF in Chinese", async () => {
    stubFetch({
      "GET /api/nodes/3/params": [],
      "POST /api/nodes/3/compare": COMPARED,
      "POST /api/nodes/3/dcf": {
        identity: COMPARED.identity,
        written: 12,
        skipped: 0,
        failed: [],
        differences: [],
        warnings: ["RPDO1 is synchronous"],
      },
    });
    const { container } = renderPage(<ParamsPage node={3} />, "/nodes/3/parameters");
    expect(await screen.findByRole("heading", { name: "无参数目录" })).toBeTruthy();
    expect(screen.getByText(/^节点 3 使用通用设备配置/)).toBeTruthy();
    const server = ["Heartbeat", "RPDO1 is synchronous"];

    await userEvent.click(screen.getByRole("button", { name: "比较…" }));
    let dialog = within(screen.getByRole("dialog", { name: "比较节点参数" }));
    expect(dialog.getByLabelText("用于比较的 DCF 文件（可选）")).toBeTruthy();
    expect(englishLeft(container, server)).toEqual([]);
    await userEvent.click(dialog.getByRole("button", { name: "比较" }));
    expect(await screen.findByText("1 个条目中有 0 个与 EDS 默认值不同")).toBeTruthy();
    expect(screen.getByLabelText("仅显示差异")).toBeTruthy();
    expect(screen.getByText("无差异。")).toBeTruthy();
    await userEvent.click(screen.getByLabelText("仅显示差异"));
    const compared = screen.getByRole("table");
    expect(
      within(compared)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["名称", "索引", "设备", "文件", "EDS 默认值", "单位"]);
    expect(englishLeft(container, server)).toEqual([]);

    await userEvent.upload(screen.getByLabelText("加载 DCF…"), new File(["x"], "plc.dcf"));
    dialog = within(await screen.findByRole("dialog", { name: "将 plc.dcf 加载到节点 3" }));
    expect(dialog.getByText("节点 3 上将有 1 个值被更改。目前尚未写入任何内容。")).toBeTruthy();
    const changes = dialog.getByRole("table", { name: "将被更改的值" });
    expect(
      within(changes)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["名称", "索引", "设备当前值", "文件中的值", "单位"]);
    expect(englishLeft(container, server)).toEqual([]);
    await userEvent.click(dialog.getByRole("button", { name: "写入 1 个值" }));

    expect(await screen.findByText("已写入 12，跳过 0，失败 0，回读后不一致 0。")).toBeTruthy();
    expect(screen.getByRole("list", { name: "已写入，但请检查" })).toBeTruthy();
    expect(englishLeft(container, server)).toEqual([]);
    expect(container.textContent).not.toMatch(/\bparams\.[a-z]/);
  });

  it("names a file for another device in Chinese", async () => {
    const question = "plc.dcf is for vendor 0x9";
    stubFetch({
      "GET /api/nodes/3/params": [],
      "POST /api/nodes/3/compare": {
        ...COMPARED,
        rows: [],
        identity: { ...COMPARED.identity, matches: false, message: question },
        confirm: [question, "a 1 ms heartbeat"],
      },
    });
    const { container } = renderPage(<ParamsPage node={3} />, "/nodes/3/parameters");
    await userEvent.upload(await screen.findByLabelText("加载 DCF…"), new File(["x"], "plc.dcf"));
    const dialog = within(await screen.findByRole("dialog", { name: "将 plc.dcf 加载到节点 3" }));
    const alert = dialog.getByRole("alert").textContent;
    expect(alert).toContain(
      `此文件适用于其他设备。 ${question}。这些值在节点 3 上的含义可能不同。`,
    );
    expect(alert).toContain("写入前请检查： a 1 ms heartbeat。");
    expect(dialog.getByRole("checkbox", { name: "仍然写入节点 3" })).toBeTruthy();
    expect(dialog.getByText("节点 3 已具有 plc.dcf 中的全部值：不会有任何更改。")).toBeTruthy();
    expect(dialog.getByRole("button", { name: "仍然写入参数集" })).toBeTruthy();
    expect(englishLeft(container, [question, "a 1 ms heartbeat", "plc.dcf"])).toEqual([]);
  });

  it("shows the node-ID change on the node's new page in Chinese", async () => {
    const notice = { oldNode: 1, newNode: 5, steps: ["wrote 5 to PA-105"] };
    stubFetch({ "GET /api/nodes/5/params": [] });
    render(
      <MemoryRouter initialEntries={[{ pathname: "/nodes/5/parameters", state: { notice } }]}>
        <LiveProvider store={new LiveStore()} connect={false}>
          <ParamsPage node={5} />
        </LiveProvider>
      </MemoryRouter>,
    );
    expect(screen.getByRole("heading", { name: "节点 1 现为节点 5" })).toBeTruthy();
    expect(screen.getByText("wrote 5 to PA-105")).toBeTruthy();
    expect(await screen.findByRole("heading", { name: "无参数目录" })).toBeTruthy();
  });
});
