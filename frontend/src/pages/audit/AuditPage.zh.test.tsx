// The Audit page in Simplified Chinese: headings, filters, columns, results and the undo from the
// zh-CN catalogue; what the entries recorded (what, role, the server's messages) stays as it
// arrives; no bare catalogue key anywhere.
import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import { LiveStore } from "../../live/store";
import { stubFetch } from "../../test/fetchStub";
import { inChinese } from "../../test/inChinese";
import { pageWords } from "../../test/pageWords";
import { renderPage, sessionAs } from "../../test/render";
import { AuditPage } from "./AuditPage";
import { FAILED, UNDO, WRITE } from "./fixtures";

inChinese();

/** The English the page showed before, none of which may be left in Chinese. */
const ENGLISH = [
  "Audit log",
  "Refresh",
  "Export CSV",
  "Audit filters",
  "Node",
  "Since",
  "User",
  "Action",
  "anyone",
  "Apply filters",
  "Clear",
  "Time",
  "Client",
  "Object",
  "Old → new",
  "Result",
  "Undo",
  "Entry 1",
  "OK",
  "Failed",
  "undoes entry",
  "undone by entry",
  "shown, newest first",
  "Load older",
  "Write ",
  "back to",
  "replacing",
  "The undo is logged",
  "Cancel",
  "Loading",
];

/** What the entries recorded (their "what" and the server's messages), not the page's words. */
const AUDIT_RECORDS = [".audit-what", ".audit-detail"];

describe("AuditPage in zh-CN", () => {
  it("shows Chinese headings, filters, columns and results, and undoes in Chinese", async () => {
    let undone = false;
    stubFetch({
      "GET /api/audit": () =>
        undone ? [UNDO, { ...WRITE, undone_by: 13, undoable: false }, FAILED] : [WRITE, FAILED],
      "POST /api/audit/12/undo": () => {
        undone = true;
        return UNDO;
      },
    });
    const { container } = renderPage(<AuditPage />, "/audit");

    const write = await screen.findByTestId("audit-12");
    expect(screen.getByRole("heading", { level: 1, name: "审计日志" })).toBeTruthy();
    expect(screen.getByRole("button", { name: "刷新" })).toBeTruthy();
    expect(screen.getByRole("link", { name: "导出 CSV" })).toBeTruthy();
    const filters = screen.getByRole("form", { name: "审计筛选" });
    expect(within(filters).getByLabelText("节点").getAttribute("placeholder")).toBe("任意");
    expect(within(filters).getByLabelText("起始时间")).toBeTruthy();
    expect(within(filters).getByLabelText("用户").getAttribute("placeholder")).toBe("任何人");
    expect(within(filters).getByLabelText("操作")).toBeTruthy();
    expect(within(filters).getByRole("button", { name: "应用筛选" })).toBeTruthy();
    expect(within(filters).getByRole("button", { name: "清除" })).toBeTruthy();
    expect(screen.getAllByRole("columnheader").map((th) => th.textContent)).toEqual([
      "时间",
      "用户",
      "客户端",
      "节点",
      "操作",
      "对象",
      "旧值 → 新值",
      "结果",
      "撤销",
    ]);
    expect(write.textContent).toContain("成功");
    expect(write.textContent).toContain("1000 → 2000");
    const failed = screen.getByTestId("audit-11");
    expect(failed.textContent).toContain("失败");
    // the abort code's meaning is the server's
    expect(failed.textContent).toContain("0x06010002 — Attempt to write a read-only object");
    expect(screen.getByText("显示 2 条，最新的在前")).toBeTruthy();
    const undo = within(write).getByRole("button", { name: "撤销条目 12" });
    expect(undo.textContent).toBe("撤销");
    expect(undo.getAttribute("title")).toBe("写回 1000");

    await userEvent.click(undo);
    const dialog = screen.getByRole("dialog", { name: "撤销条目 12" });
    expect(dialog.textContent).toContain("将 1000 写回节点 1 的 6081h:00，替换 2000？");
    expect(dialog.textContent).toContain("撤销操作本身会记录为一个新条目。");
    expect(within(dialog).getByRole("button", { name: "取消" })).toBeTruthy();
    expect(pageWords(document.body, AUDIT_RECORDS)).not.toContain("Write 1000 back");
    await userEvent.click(within(dialog).getByRole("button", { name: "写回 1000" }));

    expect((await screen.findByTestId("audit-13")).textContent).toContain("撤销条目 12");
    expect(screen.getByTestId("audit-12").textContent).toContain("已由条目 13 撤销");
    expect(screen.getByRole("status").textContent).toBe(
      "撤销已记录为条目 13，对象 6081h:00：2000 → 1000（成功）。",
    );
    expect(screen.getByText("显示 3 条，最新的在前")).toBeTruthy();

    const words = pageWords(document.body, AUDIT_RECORDS);
    for (const english of ENGLISH) expect(words, english).not.toContain(english);
    // a key the catalogue missed would show as "logs.…"
    expect(container.textContent).not.toMatch(/\blogs\.[a-z]/);
  });

  it("says in Chinese why an operator may not undo, and when nothing matches", async () => {
    stubFetch({ "GET /api/audit": [WRITE] });
    renderPage(<AuditPage />, "/audit", new LiveStore(), sessionAs("operator"));
    const undo = await screen.findByRole("button", { name: "撤销条目 12" });
    expect(undo).toHaveProperty("disabled", true);
    expect(undo.getAttribute("title")).toContain("需以工程师身份登录才能撤销修改");
    expect(screen.getByText("显示 1 条，最新的在前")).toBeTruthy();

    stubFetch({ "GET /api/audit": [] });
    await userEvent.type(screen.getByLabelText("节点"), "5");
    await userEvent.click(screen.getByRole("button", { name: "应用筛选" }));
    expect(await screen.findByText("没有符合这些筛选条件的条目。")).toBeTruthy();
  });
});
