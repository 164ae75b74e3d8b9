import { describe, expect, it, vi, type Mock } from "vitest";

import {
  emptyViewerUrl,
  sendRecording,
  viewerHandle,
  waitForViewer,
  type RerunHandle,
} from "./rerunViewer";

function fakeHandle(): RerunHandle & Record<keyof RerunHandle, Mock> {
  return {
    open_channel: vi.fn<RerunHandle["open_channel"]>(),
    send_rrd_to_channel: vi.fn<RerunHandle["send_rrd_to_channel"]>(),
    close_channel: vi.fn<RerunHandle["close_channel"]>(),
  };
}

function frameWith(handle: unknown): HTMLIFrameElement {
  const frame = document.createElement("iframe");
  document.body.append(frame);
  Object.assign(frame.contentWindow ?? {}, { _handle: handle });
  return frame;
}

describe("the rerun viewer", () => {
  it("loads without a stream for a recording handed over by bytes", () => {
    expect(emptyViewerUrl("/rerun/?url=rerun%2Bhttp%3A%2F%2Fh%2Fproxy")).toBe("/rerun/");
    expect(emptyViewerUrl("/rerun/")).toBe("/rerun/");
  });

  it("hands the .rrd to the viewer through a channel of its own", () => {
    const handle = fakeHandle();
    const bytes = new Uint8Array([1, 2, 3]);
    sendRecording(handle, "servodesk-capture-3", "ServoDesk capture 3", bytes);
    expect(handle.open_channel).toHaveBeenCalledWith("servodesk-capture-3", "ServoDesk capture 3");
    expect(handle.send_rrd_to_channel).toHaveBeenCalledWith("servodesk-capture-3", bytes);
    expect(handle.close_channel).toHaveBeenCalledWith("servodesk-capture-3");
  });

  it("finds the viewer's handle once it started, nothing else", async () => {
    expect(viewerHandle(null)).toBeNull();
    expect(viewerHandle(frameWith({ open_channel: 1 }))).toBeNull();
    const handle = fakeHandle();
    const frame = frameWith(handle);
    expect(viewerHandle(frame)).toBe(handle);
    await expect(waitForViewer(frame, new AbortController().signal)).resolves.toBe(handle);
    const stopped = new AbortController();
    stopped.abort();
    await expect(waitForViewer(frameWith(null), stopped.signal)).rejects.toThrow("closed");
  });
});
