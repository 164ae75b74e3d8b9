// The Object dictionary page in Simplified Chinese: search, tree, details, upload-all and the
// dictionary's source from the zh-CN catalogue; object names, data types, values and the
// server's messages stay as sent; none of the page's English texts left, no bare catalogue key.
import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import type { OdTree } from "../../api/types";
import { stubFetch } from "../../test/fetchStub";
import { inChinese } from "../../test/inChinese";
import { pageWords } from "../../test/pageWords";
import { renderPage, sessionAs } from "../../test/render";
import { LiveStore } from "../../live/store";
import { DEVICE_TYPE, TREE, UPLOAD_ALL } from "./fixtures";
import { OdPage } from "./OdPage";

inChinese();

/** The page's English texts, replaced by the catalogue: none may be left in Chinese. */
const ENGLISH = [
  "Objects",
  "Search",
  "a name",
  "Loading dictionary",
  " of ",
  "Select an entry",
  "Object dictionary",
  "Expand",
  "Collapse",
  "entries",
  "No entry matches",
  "Load EDS",
  "Use profile dictionary",
  "Imported",
  "Profile",
  "warning",
  "Dictionary import warnings",
  "No findings",
  "Severity",
  "Line",
  "Section",
  "Key",
  "Message",
  "read only",
  "write only",
  "read / write",
  "constant",
  "Constant",
  "Read-only",
  "in the dictionary",
  "Value",
  "Raw",
  "Text",
  "Data type",
  "Access",
  "PDO mappable",
  "yes",
  "Default",
  "Limits",
  "Unit",
  "Read",
  "New value",
  "hex bytes",
  "decimal",
  "Write",
  "Upload all",
  "Upload progress",
  "Cancel",
  "done",
  "not readable",
];

/** The page's English texts found in what it shows, the server's texts taken out. */
function englishLeft(container: HTMLElement, serverTexts: readonly string[] = []): string[] {
  const server = [
    "Device type",
    "Identity object",
    "Highest sub-index supported",
    "Vendor-ID",
    "Product code",
    "Modes of operation",
    "cia402/drive.eds",
    ...serverTexts,
  ];
  // the shared dialog frame's close button is not this page's
  const text = server.reduce(
    (rest, s) => rest.split(s).join(""),
    pageWords(container, ["[data-dialog-close]"]),
  );
  return ENGLISH.filter((english) => text.includes(english));
}

describe("OdPage in zh-CN", () => {
  it("shows the tree, the search and an entry's details in Chinese", async () => {
    stubFetch({
      "GET /api/nodes/3/od": TREE,
      "GET /api/nodes/3/sdo/1000/00": DEVICE_TYPE,
    });
    const { container } = renderPage(<OdPage node={3} />, "/nodes/3/od");
    const tree = await screen.findByRole("list", { name: "对象字典" });
    expect(document.documentElement.lang).toBe("zh-CN");
    expect(screen.getByRole("region", { name: "对象" })).toBeTruthy();
    const search = screen.getByRole("searchbox", { name: "搜索对象" });
    expect(search.getAttribute("placeholder")).toBe("搜索：6041、0x1018、1018:2 或名称");
    expect(screen.getByText("5 / 5")).toBeTruthy();
    expect(screen.getByText("选择一个条目以查看其详细信息并进行读写。")).toBeTruthy();
    expect(screen.getByRole("button", { name: "全部上传" })).toBeTruthy();
    expect(screen.getByRole("button", { name: "使用设备子协议的对象字典" })).toBeTruthy();
    expect(screen.getByLabelText("加载 EDS…")).toBeTruthy();
    expect(screen.getByTestId("od-source").textContent).toBe(
      "设备子协议: cia402/drive.eds · 0 条警告",
    );
    expect(within(tree).getByText("3 个条目")).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);

    // a record opens and closes by its toggle, named in Chinese
    await userEvent.click(screen.getByRole("button", { name: "展开 1018h Identity object" }));
    expect(screen.getByRole("button", { name: "折叠 1018h Identity object" })).toBeTruthy();
    expect(englishLeft(container)).toEqual([]);

    // a read-only entry: its facts, the read and the way to write it anyway
    await userEvent.click(screen.getByRole("button", { name: /^1000\s*Device type$/ }));
    expect(screen.getByRole("heading", { name: "Device type" })).toBeTruthy();
    expect(
      [...container.querySelectorAll(".od-details > .facts dt")].map((dt) => dt.textContent),
    ).toEqual(["数据类型", "访问类型", "可 PDO 映射", "默认值", "取值范围", "单位"]);
    expect(screen.getByText("只读")).toBeTruthy();
    expect(screen.getByText("否")).toBeTruthy();
    expect(screen.getByText(/^该条目在对象字典中为只读。/)).toBeTruthy();
    await userEvent.click(screen.getByRole("button", { name: "读取" }));
    const result = within(await screen.findByLabelText("读取的值"));
    expect(result.getByText("值")).toBeTruthy();
    expect(result.getByText("原始字节")).toBeTruthy();
    expect(result.getByText("文本")).toBeTruthy();
    expect(englishLeft(container, ["0x00020192 (131474)", "UNSIGNED32"])).toEqual([]);

    await userEvent.click(screen.getByRole("button", { name: "仍然写入…" }));
    const input = screen.getByLabelText("新值");
    expect(input.getAttribute("placeholder")).toBe("十进制或 0x 十六进制");
    expect(screen.getByRole("button", { name: "写入" })).toBeTruthy();
    expect(englishLeft(container, ["0x00020192 (131474)", "UNSIGNED32"])).toEqual([]);

    // a search that finds nothing says so in Chinese
    await userEvent.type(search, "zzzz");
    expect(await screen.findByText("没有匹配的条目。")).toBeTruthy();
    expect(screen.getByText("0 / 5")).toBeTruthy();
    expect(container.textContent).not.toMatch(/\bod\.[a-z]/);
  });

  it("uploads all values with progress in Chinese", async () => {
    stubFetch({
      "GET /api/nodes/3/od": TREE,
      ...UPLOAD_ALL,
    });
    const { container } = renderPage(<OdPage node={3} />, "/nodes/3/od");
    await userEvent.click(await screen.findByRole("button", { name: "全部上传" }));
    expect(screen.getByRole("button", { name: "取消" })).toBeTruthy();
    expect(screen.getByRole("progressbar", { name: "上传进度" })).toBeTruthy();
    expect(
      await screen.findByText("2/2 · 已完成，用时 0.3 s · 1 个不可读", {}, { timeout: 3000 }),
    ).toBeTruthy();
    const server = ["0x00000001 (1)", "0x06020000 Object does not exist in the object dictionary"];
    expect(englishLeft(container, server)).toEqual([]);
  });

  it("lists an imported file's findings in Chinese", async () => {
    const imported: OdTree = {
      ...TREE,
      source: "upload",
      filename: "uploads/vendor.eds",
      warnings: [
        {
          code: "bad-default",
          file: "vendor.eds",
          line: 42,
          section: "6060",
          key: "DefaultValue",
          message: "DefaultValue is not a number",
          severity: "warning",
        },
      ],
    };
    stubFetch({ "GET /api/nodes/3/od": imported });
    const { container } = renderPage(
      <OdPage node={3} />,
      "/nodes/3/od",
      new LiveStore(),
      sessionAs("viewer"),
    );
    await screen.findByRole("list", { name: "对象字典" });
    expect(screen.getByTestId("od-source").textContent).toBe(
      "已导入: uploads/vendor.eds · 1 条警告",
    );
    expect(
      screen.getByRole("button", { name: "使用设备子协议的对象字典" }).getAttribute("title"),
    ).toContain("才能更改对象字典");
    await userEvent.click(screen.getByRole("button", { name: "1 条警告" }));
    const table = screen.getByRole("table", { name: "对象字典导入警告" });
    expect(
      within(table)
        .getAllByRole("columnheader")
        .map((th) => th.textContent),
    ).toEqual(["严重程度", "行", "节", "键", "信息"]);
    expect(within(table).getByText("警告")).toBeTruthy();
    const server = ["DefaultValue is not a number", "DefaultValue", "uploads/vendor.eds"];
    expect(englishLeft(container, server)).toEqual([]);
    expect(container.textContent).not.toMatch(/\b(od|common)\.[a-z]/);
  });
});
