import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { CHECKED } from "./fixtures";
import { ToolsPage } from "./ToolsPage";

afterEach(() => {
  vi.unstubAllGlobals();
});

describe("ToolsPage", () => {
  it("checks an EDS file and lists its findings", async () => {
    const fetch = stubFetch({
      "POST /api/od/check": CHECKED,
    });
    renderPage(<ToolsPage />, "/tools");
    const file = new File(["[FileInfo]\nFileName=drive.eds\n"], "drive.eds", {
      type: "text/plain",
    });
    await userEvent.upload(screen.getByLabelText("Choose EDS file to check…"), file);

    expect(await screen.findByText("227")).toBeTruthy();
    expect(screen.getByText("1 errors, 0 warnings, 1 notes")).toBeTruthy();
    expect(screen.getByText("DefaultValue is empty")).toBeTruthy();
    expect(screen.getByText("Unknown data type")).toBeTruthy();
    const post = fetch.calls.find((c) => c.path === "/api/od/check");
    // Sent as multipart with the field the route expects (jsdom's File does not carry its
    // name into Node's fetch, so the file name itself is not checked here).
    expect(post?.body).toContain('name="file"');
  });
});
