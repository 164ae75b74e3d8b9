// Opening a finished capture in the embedded rerun viewer.
//
// rerun's web viewer (0.41) opens an http URL only when its *path* ends in ".rrd": the export
// route (/api/scope/captures/{id}/export?format=rrd) ends in a query, which the viewer refuses
// ("Failed to parse URL"). So the page loads the viewer without a stream and hands it the
// capture's bytes through the viewer's own channel API (the WebHandle its index.html keeps as
// `window._handle`: open_channel, send_rrd_to_channel, close_channel), as rerun's notebook
// widget does. The viewer is same-origin (/rerun/ under ServoDesk), so the page may call it.

/** The part of rerun's WebHandle used here. */
export interface RerunHandle {
  open_channel: (id: string, name: string) => void;
  send_rrd_to_channel: (id: string, data: Uint8Array) => void;
  close_channel: (id: string) => void;
}

function isHandle(value: unknown): value is RerunHandle {
  if (typeof value !== "object" || value === null) return false;
  const handle = value as Record<string, unknown>;
  return (
    typeof handle.open_channel === "function" &&
    typeof handle.send_rrd_to_channel === "function" &&
    typeof handle.close_channel === "function"
  );
}

/** The viewer's handle once its app has started (null before, or when it is not rerun). */
export function viewerHandle(frame: HTMLIFrameElement | null): RerunHandle | null {
  try {
    const win: unknown = frame?.contentWindow;
    const handle: unknown =
      typeof win === "object" && win !== null ? Reflect.get(win, "_handle") : undefined;
    return isHandle(handle) ? handle : null;
  } catch {
    return null; // another origin: not the app's viewer
  }
}

/** Wait for the viewer in `frame` to start (WebGL on a software rasteriser takes seconds). */
export function waitForViewer(
  frame: HTMLIFrameElement,
  signal: AbortSignal,
  timeoutMs = 30_000,
): Promise<RerunHandle> {
  return new Promise((resolve, reject) => {
    const started = Date.now();
    const check = (): void => {
      if (signal.aborted) {
        reject(new DOMException("The viewer was closed", "AbortError"));
        return;
      }
      const handle = viewerHandle(frame);
      if (handle) {
        resolve(handle);
      } else if (Date.now() - started > timeoutMs) {
        reject(new Error("the rerun viewer did not start within 30 s; reload the page"));
      } else {
        setTimeout(check, 200);
      }
    };
    check();
  });
}

/** Hand a recording's bytes to the viewer; it shows it as a recording of its own. */
export function sendRecording(
  handle: RerunHandle,
  id: string,
  name: string,
  rrd: Uint8Array,
): void {
  handle.open_channel(id, name);
  try {
    handle.send_rrd_to_channel(id, rrd);
  } finally {
    handle.close_channel(id);
  }
}

/** The viewer page without a stream: ".../rerun/?url=..." → ".../rerun/". */
export function emptyViewerUrl(liveUrl: string): string {
  const query = liveUrl.indexOf("?");
  return query < 0 ? liveUrl : liveUrl.slice(0, query);
}
