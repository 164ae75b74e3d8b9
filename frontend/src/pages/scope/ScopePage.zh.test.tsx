// The Scope page in Simplified Chinese: headings, buttons, columns and capture states from the
// zh-CN catalogue; no bare catalogue key anywhere.
import { act, screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it } from "vitest";

import { i18n } from "../../i18n";
import { LiveStore } from "../../live/store";
import { inChinese } from "../../test/inChinese";
import { stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { INFO, PLAN, TREE, VIEWER, capture } from "./fixtures";
import { ScopePage } from "./ScopePage";

inChinese();

afterEach(() => {
  window.sessionStorage.clear();
  window.localStorage.removeItem("servodesk.scope.liveView");
});

describe("ScopePage in zh-CN", () => {
  it("shows Chinese headings, buttons, columns and capture states", async () => {
    stubFetch({
      "GET /api/scope/viewer": VIEWER,
      "GET /api/scope/captures": [capture({ id: 5, state: "done", ended: 1_790_000_003 })],
      "GET /api/nodes/1/od": TREE,
      "POST /api/scope/plan": PLAN,
    });
    const store = new LiveStore();
    store.upsertInfo(INFO);
    const { container } = renderPage(<ScopePage />, "/scope", store);

    expect(screen.getByRole("heading", { level: 1 }).textContent).toBe("示波器");
    await userEvent.click(await screen.findByRole("button", { name: "位置 6064h" }));
    await userEvent.click(screen.getByRole("button", { name: "速度 606Ch" }));
    const sources = await screen.findByRole("table", { name: "信号来源" });
    expect(
      within(sources)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["信号", "来源", "单位", "说明"]);
    const headings = screen.getAllByRole("heading", { level: 2 }).map((h) => h.textContent);
    for (const heading of ["信号", "采集", "检查", "查看器", "采集记录"]) {
      expect(headings).toContain(heading);
    }
    const start = screen.getByRole("button", { name: "● 开始采集" });
    await waitFor(() => expect(start).toHaveProperty("disabled", false));
    expect(screen.getByRole("list", { name: "已选信号" })).toBeTruthy();

    const list = await screen.findByRole("table", { name: "采集记录" });
    expect(within(list).getByText("完成")).toBeTruthy();
    expect(screen.getByRole("button", { name: "在查看器中打开采集 5" })).toBeTruthy();
    expect(screen.getByRole("button", { name: "删除采集 5" })).toBeTruthy();
    expect(screen.getByRole("heading", { name: "光标" })).toBeTruthy();

    // the live view switch, and the panel while paused
    await userEvent.click(screen.getByRole("button", { name: "暂停实时视图" }));
    expect(screen.queryByTestId("rerun-viewer")).toBeNull();
    expect(screen.getByTestId("live-view-paused").textContent).toBe(
      "实时视图已暂停：采集仍会照常记录，完成后可从列表中打开。",
    );
    expect(screen.getByRole("button", { name: "显示实时视图" })).toBeTruthy();
    for (const english of [
      "Pause live view",
      "Show live view",
      "Live view paused",
      "still record",
    ]) {
      expect(container.textContent).not.toContain(english);
    }

    // a key the catalogue missed would show as "scope.…"
    expect(container.textContent).not.toMatch(/\bscope\.[a-z]/);
  });

  it("says why Start is off in the language just chosen, without an edit", async () => {
    await i18n.changeLanguage("en");
    stubFetch({
      "GET /api/scope/viewer": VIEWER,
      "GET /api/scope/captures": [],
      "GET /api/nodes/1/od": TREE,
    });
    const store = new LiveStore();
    store.upsertInfo(INFO);
    renderPage(<ScopePage />, "/scope", store);
    const reason = await screen.findByText(i18n.t("scope.problem.noSignal"));
    expect(reason.id).toBe("scope-start-reason");
    const english = reason.textContent;
    await act(() => i18n.changeLanguage("zh-CN"));
    const now = document.getElementById("scope-start-reason")?.textContent;
    expect(now).toBe(i18n.t("scope.problem.noSignal"));
    expect(now).not.toBe(english);
  });
});
