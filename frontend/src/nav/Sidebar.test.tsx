import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it } from "vitest";

import { LANGUAGE_STORAGE_KEY } from "../i18n";
import { renderPage } from "../test/render";
import { Sidebar } from "./Sidebar";

describe("Sidebar language switch", () => {
  it("switches the whole sidebar at once and remembers the choice", async () => {
    renderPage(<Sidebar />);
    expect(screen.getByRole("link", { name: "Network" })).toBeTruthy();
    expect(screen.getByRole("status").textContent).toBe("Live: connecting…");
    expect(document.documentElement.lang).toBe("en");

    await userEvent.selectOptions(
      screen.getByRole("combobox", { name: "Language / 语言" }),
      "简体中文",
    );

    expect(screen.getByRole("link", { name: "网络" })).toBeTruthy();
    expect(screen.getByRole("navigation", { name: "主导航" })).toBeTruthy();
    expect(screen.getByText("暂无节点：请在“网络”页面连接总线并扫描。")).toBeTruthy();
    expect(screen.getByRole("status").textContent).toBe("实时连接：正在连接…");
    expect(localStorage.getItem(LANGUAGE_STORAGE_KEY)).toBe("zh-CN");
    expect(document.documentElement.lang).toBe("zh-CN");
  });
});
