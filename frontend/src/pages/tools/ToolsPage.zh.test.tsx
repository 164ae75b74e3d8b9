// The Tools page in Simplified Chinese: headings, the file summary and the finding counts from
// the zh-CN catalogue; the findings themselves stay as the server words them; no bare key.
import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import { stubFetch } from "../../test/fetchStub";
import { inChinese } from "../../test/inChinese";
import { pageWords } from "../../test/pageWords";
import { renderPage } from "../../test/render";
import { CHECKED } from "./fixtures";
import { ToolsPage } from "./ToolsPage";

inChinese();

/** The English the page's own parts showed before (the findings table is a shared component). */
const ENGLISH = [
  "Tools",
  "Check an EDS file",
  "Choose EDS file to check",
  "Checking",
  "Reads an EDS",
  "File summary",
  "File",
  "Format",
  "Objects",
  "Vendor",
  "Product",
  "Findings",
  "errors",
  "warnings",
  "notes",
];

describe("ToolsPage in zh-CN", () => {
  it("checks an EDS file with Chinese headings and summary", async () => {
    stubFetch({
      "POST /api/od/check": CHECKED,
    });
    const { container } = renderPage(<ToolsPage />, "/tools");
    expect(screen.getByRole("heading", { level: 1, name: "工具" })).toBeTruthy();
    expect(screen.getByRole("heading", { level: 2, name: "检查 EDS 文件" })).toBeTruthy();
    const file = new File(["[FileInfo]\nFileName=drive.eds\n"], "drive.eds", {
      type: "text/plain",
    });
    await userEvent.upload(screen.getByLabelText("选择要检查的 EDS 文件…"), file);

    const summary = await screen.findByLabelText("文件摘要");
    expect([...summary.querySelectorAll("dt")].map((dt) => dt.textContent)).toEqual([
      "文件",
      "格式",
      "对象数",
      "厂商",
      "产品",
      "检查结果",
    ]);
    expect(screen.getByText("227")).toBeTruthy();
    expect(screen.getByText("1 个错误，0 个警告，1 个提示")).toBeTruthy();
    expect(screen.getByRole("table", { name: "drive.eds 的检查结果" })).toBeTruthy();
    // the findings are the server's
    expect(screen.getByText("DefaultValue is empty")).toBeTruthy();

    // the findings (the table in .lint-scroll) are the server's words
    const words = pageWords(container, [".lint-scroll"]);
    for (const english of ENGLISH) expect(words, english).not.toContain(english);
    // a key the catalogue missed would show as "logs.…"
    expect(container.textContent).not.toMatch(/\blogs\.[a-z]/);
  });
});
