// The Logs page in Simplified Chinese: headings, columns, buttons and totals from the zh-CN
// catalogue; the server's summary and decoded events stay as they arrive; no bare catalogue key.
import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import { stubFetch } from "../../test/fetchStub";
import { inChinese } from "../../test/inChinese";
import { pageWords } from "../../test/pageWords";
import { renderPage } from "../../test/render";
import { decoded, event, kept, notRecording } from "./fixtures";
import { LogsPage } from "./LogsPage";

inChinese();

/** The English the page showed before, none of which may be left in Chinese. */
const ENGLISH = [
  "Logs",
  "Analyse a CAN log",
  "The server decodes",
  "Choose CAN log",
  "Choose DCF",
  "Drives (optional)",
  "Which drive a node is",
  "Summary of",
  "Export events",
  "Log totals",
  "Events by kind",
  "Frames",
  "Duration",
  "Node ids",
  "Bitrate",
  "Decoded events",
  "Hide ServoDesk",
  "Previous",
  "Next",
  "Events 1",
  "Loading",
  "Decoded logs",
  "kept",
  "Open",
  "Delete",
  "Record the bus",
  "Not recording",
  "Start recording",
  "Format",
];

/** The server's summary lines and decoded events, not the page's words. */
const SERVER_TEXTS = [".log-summary", ".event-table tbody"];

describe("LogsPage in zh-CN", () => {
  it("shows Chinese headings, totals, columns and buttons", async () => {
    stubFetch({
      "GET /api/recording": notRecording,
      "GET /api/logs": kept,
      "POST /api/logs/decode": decoded,
      "GET /api/logs/abc123/events": { events: [event(500, "emcy", "late 0")], next: null },
    });
    const { container } = renderPage(<LogsPage />, "/logs");

    expect(screen.getByRole("heading", { level: 1, name: "日志" })).toBeTruthy();
    expect(await screen.findByText("未在录制")).toBeTruthy();
    expect(screen.getByRole("button", { name: "开始录制" })).toBeTruthy();
    expect(screen.getByLabelText("格式")).toBeTruthy();
    expect(screen.getByLabelText("驱动器（可选）").getAttribute("title")).toMatch(/^日志中没有/);

    const table = await screen.findByRole("table", { name: "已解码的日志" });
    expect(
      within(table)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["日志", "解码时间", "大小", "打开 · 删除"]);
    expect(screen.getByText("已保存 2 个")).toBeTruthy();

    await userEvent.upload(screen.getByLabelText("选择 CAN 日志…"), new File(["x"], "bus.log"));
    expect(await screen.findByRole("list", { name: "摘要" })).toBeTruthy();
    expect(screen.getAllByRole("heading", { level: 2 }).map((h) => h.textContent)).toEqual([
      "分析 CAN 日志",
      "bus.log 摘要",
      "解码事件",
      "已解码的日志",
      "录制总线",
    ]);
    const totals = screen.getByLabelText("日志统计");
    expect(totals.textContent).toContain("帧数1,200");
    expect(totals.textContent).toContain("总线负载峰值 3.1 %，平均 1.2 %");
    expect(totals.textContent).toContain("波特率500 kbit/s");
    expect(screen.getByText("按类型统计事件：sdo 600 · emcy 1")).toBeTruthy();
    expect(screen.getByText("导出事件：")).toBeTruthy();
    expect(await screen.findByText("事件 1–500，共 700 条")).toBeTruthy();
    expect(screen.getByLabelText("隐藏 ServoDesk 自身的轮询")).toBeTruthy();
    expect(screen.getByRole("button", { name: "重新解码 bus.log" })).toBeTruthy();
    // the server's summary stays as it arrives
    expect(screen.getByText("1 EMCY(s), 0 SDO abort(s), 0 heartbeat loss(es).")).toBeTruthy();

    await userEvent.click(screen.getByRole("button", { name: "下一页 →" }));
    expect(await screen.findByText("事件 501–501，共 700 条")).toBeTruthy();
    expect(screen.getByRole("button", { name: "← 上一页" })).toBeTruthy();

    // the list is read again after the decode: its table anew
    const [, , oldest] = within(
      await screen.findByRole("table", { name: "已解码的日志" }),
    ).getAllByRole("row");
    if (!oldest) throw new Error("two logs listed");
    expect(within(oldest).getByRole("button", { name: "打开" })).toBeTruthy();
    await userEvent.click(within(oldest).getByRole("button", { name: "删除" }));
    const dialog = screen.getByRole("dialog", { name: "删除 old.blf？" });
    expect(within(dialog).getByRole("button", { name: "删除 old.blf" })).toBeTruthy();
    expect(within(dialog).getByRole("button", { name: "取消" })).toBeTruthy();
    expect(dialog.textContent).toMatch(/将从服务器删除 old\.blf（2 KiB，解码于 \d{4}-/);

    const words = pageWords(document.body, SERVER_TEXTS);
    for (const english of ENGLISH) expect(words, english).not.toContain(english);
    // a key the catalogue missed would show as "logs.…"
    expect(container.textContent).not.toMatch(/\blogs\.[a-z]/);
  });

  it("says what the recording holds in Chinese", async () => {
    stubFetch({
      "GET /api/recording": {
        active: true,
        format: "asc",
        file: "rec.asc",
        since: Date.now() / 1000,
        frames: 1234,
        dropped: 3,
      },
      "GET /api/logs": [],
    });
    renderPage(<LogsPage />, "/logs");
    expect(await screen.findByText(/^正在录制 ASC：1,234 帧，[\d.]+ s（丢弃 3 帧）$/)).toBeTruthy();
    expect(screen.getByRole("button", { name: "停止并下载" })).toBeTruthy();
    expect(await screen.findByText("没有保存的已解码日志。")).toBeTruthy();
    const words = pageWords(document.body, SERVER_TEXTS);
    for (const english of ["Recording", "frames", "dropped", "Stop and download", "No decoded"]) {
      expect(words, english).not.toContain(english);
    }
  });
});
