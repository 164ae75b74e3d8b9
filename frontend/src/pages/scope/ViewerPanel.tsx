import { useEffect, useId, useRef, useState, type ReactNode } from "react";

import { asApiError, type ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useApi } from "../../lib/useApi";
import { emptyViewerUrl, sendRecording, waitForViewer } from "./rerunViewer";
import { fetchRrd, scopeViewer } from "./scopeApi";

/** A finished capture to show instead of the live stream; `nonce` reopens the same one. */
export interface OpenedCapture {
  id: number;
  name: string | null;
  nonce: number;
}

/** Whether the live viewer is shown, per browser: on a machine without a GPU the viewer draws in
 * software on the page's own thread, and a live capture can then hold the whole page up. */
export const LIVE_VIEW_KEY = "servodesk.scope.liveView";

function loadLiveView(): boolean {
  try {
    return window.localStorage.getItem(LIVE_VIEW_KEY) !== "paused";
  } catch {
    return true; // storage blocked
  }
}

function saveLiveView(shown: boolean): void {
  try {
    window.localStorage.setItem(LIVE_VIEW_KEY, shown ? "shown" : "paused");
  } catch {
    // storage blocked: the choice holds until the page is left
  }
}

interface Loading {
  key: string;
  shown: boolean;
  error: ApiError | null;
}

/** rerun's own web viewer, embedded: the live stream of every capture as it records, or one
 * finished capture from its recording (.rrd). The live view can be paused (no frame, no stream);
 * a capture opened from the list is still shown then, the user asked for it. */
export function ViewerPanel({
  opened,
  onLive,
}: {
  opened: OpenedCapture | null;
  onLive: () => void;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const viewer = useApi((signal) => scopeViewer(signal), "scope-viewer");
  const frame = useRef<HTMLIFrameElement>(null);
  const [loading, setLoading] = useState<Loading | null>(null);
  const [liveShown, setLiveShown] = useState(loadLiveView);
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
  const paused = !opened && !liveShown;
  const src = live === null || paused ? null : opened ? emptyViewerUrl(live) : live;
  const toggleLive = (): void => {
    saveLiveView(!liveShown);
    setLiveShown(!liveShown);
  };
  return (
    <section className="card scope-viewer" aria-labelledby={`${id}-h`}>
      <header className="card-header">
        <h2 id={`${id}-h`}>{t("scope.viewer.heading")}</h2>
        {opened ? (
          <>
            <span className="badge">
              {opened.name
                ? t("scope.viewer.openedNamed", { id: opened.id, name: opened.name })
                : t("scope.viewer.opened", { id: opened.id })}
            </span>
            {!status && <Spinner label={t("scope.viewer.loadingCapture", { id: opened.id })} />}
            <button type="button" className="small" onClick={onLive}>
              {liveShown ? t("scope.viewer.back") : t("scope.viewer.close")}
            </button>
          </>
        ) : (
          <>
            <span className={paused ? "badge" : "badge scope-live-badge"}>
              {paused ? t("scope.viewer.pausedBadge") : t("scope.viewer.live")}
            </span>
            <button type="button" className="small" onClick={toggleLive}>
              {paused ? t("scope.viewer.show") : t("scope.viewer.pause")}
            </button>
          </>
        )}
        <span className="spacer" />
        {viewer.data && (
          <span className="muted small">
            {t("scope.viewer.served", { version: viewer.data.version })}
            {!opened && (
              <>
                {" · "}
                <a href={viewer.data.url} target="_blank" rel="noreferrer">
                  {t("scope.viewer.newTab")}
                </a>
              </>
            )}
          </span>
        )}
      </header>
      <ErrorText error={viewer.error} onRetry={viewer.reload} />
      <ErrorText error={status?.error} />
      {viewer.data && !viewer.data.running && (
        <p className="error-text">{t("scope.viewer.notRunning")}</p>
      )}
      {paused ? (
        <p className="muted scope-paused-note" data-testid="live-view-paused">
          {t("scope.viewer.pausedNote")}
        </p>
      ) : src !== null ? (
        <iframe
          key={frameKey}
          ref={frame}
          className="scope-frame"
          title={t("scope.viewer.frameTitle")}
          src={src}
          allow="fullscreen"
          data-testid="rerun-viewer"
        />
      ) : (
        !viewer.error && (
          <div className="scope-frame scope-frame-empty">
            <Spinner label={t("scope.viewer.startingLabel")} /> {t("scope.viewer.starting")}
          </div>
        )
      )}
    </section>
  );
}
