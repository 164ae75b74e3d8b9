import { useEffect, useId, useRef, useState, type ReactNode } from "react";

import { asApiError, type ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useApi } from "../../lib/useApi";
import { emptyViewerUrl, sendRecording, waitForViewer } from "./rerunViewer";
import { fetchRrd, scopeViewer } from "./scopeApi";

/** A finished capture to show instead of the live stream; `nonce` reopens the same one. */
export interface OpenedCapture {
  id: number;
  name: string | null;
  nonce: number;
}

interface Loading {
  key: string;
  shown: boolean;
  error: ApiError | null;
}

/** rerun's own web viewer, embedded: the live stream of every capture as it records, or one
 * finished capture from its recording (.rrd). */
export function ViewerPanel({
  opened,
  onLive,
}: {
  opened: OpenedCapture | null;
  onLive: () => void;
}): ReactNode {
  const id = useId();
  const viewer = useApi((signal) => scopeViewer(signal), "scope-viewer");
  const frame = useRef<HTMLIFrameElement>(null);
  const [loading, setLoading] = useState<Loading | null>(null);
  const live = viewer.data?.url ?? null;
  const frameKey = opened ? `capture-${opened.id}-${opened.nonce}` : "live";
  const openedId = opened?.id ?? null;
  const openedName = opened?.name ?? null;

  useEffect(() => {
    const element = frame.current;
    if (openedId === null || live === null || element === null) return;
    const controller = new AbortController();
    const label = `ServoDesk capture ${openedId}${openedName ? ` · ${openedName}` : ""}`;
    Promise.all([
      fetchRrd(openedId, controller.signal),
      waitForViewer(element, controller.signal),
    ]).then(
      ([rrd, handle]) => {
        if (controller.signal.aborted) return;
        sendRecording(handle, `servodesk-capture-${openedId}`, label, rrd);
        setLoading({ key: frameKey, shown: true, error: null });
      },
      (error: unknown) => {
        if (!controller.signal.aborted) {
          setLoading({ key: frameKey, shown: false, error: asApiError(error) });
        }
      },
    );
    return () => controller.abort();
  }, [openedId, openedName, live, frameKey]);

  const status = loading?.key === frameKey ? loading : null;
  const src = live === null ? null : opened ? emptyViewerUrl(live) : live;
  return (
    <section className="card scope-viewer" aria-labelledby={`${id}-h`}>
      <header className="card-header">
        <h2 id={`${id}-h`}>Viewer</h2>
        {opened ? (
          <>
            <span className="badge">
              Capture {opened.id}
              {opened.name ? ` · ${opened.name}` : ""} from its recording (.rrd)
            </span>
            {!status && <Spinner label={`Loading capture ${opened.id} into the viewer`} />}
            <button type="button" className="small" onClick={onLive}>
              Back to the live view
            </button>
          </>
        ) : (
          <span className="badge scope-live-badge">Live: every capture as it records</span>
        )}
        <span className="spacer" />
        {viewer.data && (
          <span className="muted small">
            rerun&apos;s own viewer (rerun {viewer.data.version}), served by ServoDesk: it works
            offline
            {!opened && (
              <>
                {" · "}
                <a href={viewer.data.url} target="_blank" rel="noreferrer">
                  open in a new tab
                </a>
              </>
            )}
          </span>
        )}
      </header>
      <ErrorText error={viewer.error} onRetry={viewer.reload} />
      <ErrorText error={status?.error} />
      {viewer.data && !viewer.data.running && (
        <p className="error-text">The rerun viewer is not running: reload the page to start it.</p>
      )}
      {src !== null ? (
        <iframe
          key={frameKey}
          ref={frame}
          className="scope-frame"
          title="rerun viewer"
          src={src}
          allow="fullscreen"
          data-testid="rerun-viewer"
        />
      ) : (
        !viewer.error && (
          <div className="scope-frame scope-frame-empty">
            <Spinner label="Starting the viewer" /> Starting the rerun viewer…
          </div>
        )
      )}
    </section>
  );
}
