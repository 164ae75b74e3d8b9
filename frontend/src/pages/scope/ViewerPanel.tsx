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
  const { t } = useTranslation();
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
              {t("scope.viewer.back")}
            </button>
          </>
        ) : (
          <span className="badge scope-live-badge">{t("scope.viewer.live")}</span>
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
      {src !== null ? (
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
