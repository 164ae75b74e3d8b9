import { render, screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { describe, expect, it, vi } from "vitest";

import type { CompareResult } from "../../api/types";
import { LoadDcfDialog } from "./LoadDcfDialog";

const HEARTBEAT =
  "fast.dcf sets a heartbeat every 1 ms (1017h): 1000 frames/s from one node; below 10 ms needs confirm";

function preview(overrides: Partial<CompareResult>): CompareResult {
  return {
    rows: [],
    read_only: [],
    identity: {
      matches: true,
      file: "vendor 0x0000026C",
      device: "vendor 0x0000026C",
      checked: true,
    },
    confirm: [],
    ...overrides,
  };
}

function show(result: CompareResult, onWrite = vi.fn()): typeof onWrite {
  render(
    <LoadDcfDialog
      node={3}
      filename="fast.dcf"
      preview={result}
      busy={false}
      error={null}
      onWrite={onWrite}
      onClose={() => undefined}
    />,
  );
  return onWrite;
}

describe("LoadDcfDialog", () => {
  it("asks before a set with a 1 ms heartbeat is written", async () => {
    const onWrite = show(preview({ confirm: [HEARTBEAT] }));
    expect(screen.getByRole("alert").textContent).toContain(`Check before writing: ${HEARTBEAT}`);
    const write = screen.getByRole<HTMLButtonElement>("button", { name: /write the set anyway/i });
    expect(write.disabled).toBe(true);
    await userEvent.click(screen.getByRole("checkbox", { name: /write it to node 3 anyway/i }));
    await userEvent.click(write);
    expect(onWrite).toHaveBeenCalledWith(true);
  });

  it("names a file without identity as one that cannot be checked", () => {
    const message = "bare.dcf names no device (no vendor, product or device type …)";
    show(
      preview({
        identity: {
          matches: false,
          checked: false,
          file: "no identity",
          device: "vendor 0x26C",
          message,
        },
        confirm: [message],
      }),
    );
    const alert = screen.getByRole("alert").textContent;
    expect(alert).toContain("This file cannot be checked against the node.");
    expect(alert).not.toContain("for another device");
  });

  it("writes a set for this device without a question", async () => {
    const onWrite = show(preview({}));
    expect(screen.queryByRole("alert")).toBeNull();
    await userEvent.click(screen.getByRole("button", { name: /write the set anyway/i }));
    expect(onWrite).toHaveBeenCalledWith(false);
  });
});
