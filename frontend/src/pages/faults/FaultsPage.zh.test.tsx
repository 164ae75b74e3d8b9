// The Faults page in Simplified Chinese: headings, columns and buttons from the zh-CN
// catalogue; the fault texts stay as the server sends them; no bare catalogue key anywhere.
import { screen, within } from "@testing-library/react";
import { describe, expect, it, vi } from "vitest";

import { inChinese } from "../../test/inChinese";
import { stubFetch } from "../../test/fetchStub";
import { mdiAlarm4 } from "../../test/fixtures/faults";
import { renderPage } from "../../test/render";
import { FaultsPage } from "./FaultsPage";

inChinese();

describe("FaultsPage in zh-CN", () => {
  it("shows Chinese headings, columns and buttons", async () => {
    stubFetch({
      "GET /api/nodes/1/faults": {
        active: mdiAlarm4(),
        history: [mdiAlarm4({ time: 1_764_000_000 }), mdiAlarm4({ time: 1_764_000_000.5 })],
        total: 5,
      },
      "GET /api/nodes/1/sdo/603F/00": {
        node: 1,
        index: 0x603f,
        subindex: 0,
        value: 4,
        text: "4",
        raw_hex: "",
      },
      "GET /api/nodes/1/faults/device-history": {
        node: 1,
        supported: true,
        count: 0,
        entries: [],
        error_code: null,
        note: null,
      },
    });
    const { container } = renderPage(<FaultsPage node={1} />, "/nodes/1/faults");

    expect(await screen.findByRole("heading", { name: "故障中：报警 4 位置超差" })).toBeTruthy();
    expect(screen.getAllByRole("heading", { level: 2 }).map((h) => h.textContent)).toEqual([
      "故障中：报警 4 位置超差",
      "故障历史",
      "驱动器错误历史 1003h",
    ]);
    expect(screen.getByRole("button", { name: "故障复位" })).toBeTruthy();
    expect(screen.getByRole("button", { name: "读取 1003h" })).toBeTruthy();
    expect(await screen.findByRole("button", { name: "更早…" })).toBeTruthy();
    expect(screen.getByText("已存储 5 条 EMCY，显示最新 2 条")).toBeTruthy();
    expect(screen.getByText("错误寄存器 1001h")).toBeTruthy();
    const table = screen.getByRole("table", { name: "故障历史" });
    expect(
      within(table)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["时间", "代码", "含义", "错误寄存器", "状态 前 → 后"]);
    expect(await screen.findByText("驱动器错误历史为空。")).toBeTruthy();
    await vi.waitFor(() =>
      expect(document.querySelector(".error-code-line")?.textContent).toMatch(
        /^驱动器错误代码 603Fh：0x0004/,
      ),
    );

    // a key the catalogue missed would show as "faults.…"
    expect(container.textContent).not.toMatch(/\bfaults\.[a-z]/);
  });
});
