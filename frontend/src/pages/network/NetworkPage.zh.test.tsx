// The Network page in Simplified Chinese: headings, table and status texts from the zh-CN
// catalogue, no English left in the headings, no bare catalogue key anywhere.
import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import { inChinese } from "../../test/inChinese";
import { stubFetch } from "../../test/fetchStub";
import { INFO } from "../../test/fixtures/node";
import { renderPage } from "../../test/render";
import { NetworkPage } from "./NetworkPage";

inChinese();

describe("NetworkPage in zh-CN", () => {
  it("shows Chinese headings, columns and states", async () => {
    stubFetch({
      "GET /api/bus/interfaces": [],
      "GET /api/events": { events: [], next: null },
      "POST /api/scan": { nodes: [INFO], duration_ms: 57 },
      "GET /api/nodes/1/heartbeat": { producer_ms: 100 },
    });
    const { container } = renderPage(<NetworkPage />);

    expect(document.documentElement.lang).toBe("zh-CN");
    expect(screen.getByRole("heading", { level: 1 }).textContent).toBe("网络");
    expect(screen.getAllByRole("heading", { level: 2 }).map((h) => h.textContent)).toEqual([
      "CAN 总线",
      "节点",
      "事件时间线",
    ]);
    expect(screen.getByRole("heading", { level: 3 }).textContent).toBe("连接");
    expect(screen.getByText("暂无已知节点。请先连接总线，再点击“扫描”。")).toBeTruthy();

    await userEvent.click(screen.getByRole("button", { name: "扫描" }));
    expect(await screen.findByText("找到 1 个节点，用时 57 ms")).toBeTruthy();
    const table = screen.getByRole("table", { name: "节点" });
    const columns = within(table)
      .getAllByRole("columnheader")
      .map((th) => th.textContent);
    expect(columns).toEqual([
      "节点",
      "名称",
      "设备配置",
      "标识",
      "NMT 状态",
      "距上次心跳",
      "心跳生产者时间",
      "命令",
      "记录",
      "运动",
    ]);
    expect(within(table).getByText("预操作", { selector: ".badge" })).toBeTruthy();
    expect(screen.getByRole("button", { name: "快速停止节点 1" })).toBeTruthy();
    expect(screen.getByRole("group", { name: "NMT 广播" })).toBeTruthy();

    // a key the catalogue missed would show as "network.…" or "nmt.…"
    expect(container.textContent).not.toMatch(/\b(network|nmt|nav|quickStop|status)\.[a-z]/);
  });
});
