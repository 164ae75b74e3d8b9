import { useEffect, useRef, useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import { asApiError, type ApiError } from "../../api/errors";
import type { Job, JobResult } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { type MessageKey, useTranslation } from "../../i18n";

export const POLL_MS = 250;

const STATE_WORDS = {
  running: "od.upload.state.running",
  done: "od.upload.state.done",
  cancelled: "od.upload.state.cancelled",
  failed: "od.upload.state.failed",
} as const satisfies Record<Job["state"], MessageKey>;

interface Props {
  node: number;
  /** Called with each batch of results not reported before. */
  onResults: (results: readonly JobResult[]) => void;
}

const unreadable = (result: JobResult): boolean => Boolean(result.abort_code ?? result.message);

/** "Upload all": read every readable entry as a server-side job, with progress and Cancel. */
export function UploadAll({ node, onResults }: Props): ReactNode {
  const { t } = useTranslation();
  const [job, setJob] = useState<Job | null>(null);
  const [failed, setFailed] = useState(0);
  const [error, setError] = useState<ApiError | null>(null);
  // Results arrive in pieces (the poll asks only for those it has not seen): count them here.
  const seen = useRef({ results: 0, failed: 0 });
  const onResultsRef = useRef(onResults);
  useEffect(() => {
    onResultsRef.current = onResults;
  });

  function absorb(next: Job): void {
    const counted = seen.current;
    const fresh = next.results.slice(Math.max(0, counted.results - next.results_from));
    counted.results = Math.max(counted.results, next.results_from + next.results.length);
    counted.failed += fresh.filter(unreadable).length;
    setJob(next);
    setFailed(counted.failed);
    if (fresh.length > 0) onResultsRef.current(fresh);
  }
  const absorbRef = useRef(absorb);
  useEffect(() => {
    absorbRef.current = absorb;
  });

  const running = job?.state === "running";
  const jobId = running ? job.id : null;
  useEffect(() => {
    if (jobId === null) return undefined;
    let cancelled = false;
    let timer: ReturnType<typeof setTimeout> | undefined;
    const poll = async (): Promise<void> => {
      try {
        const next = await call(
          api.GET("/api/jobs/{job_id}", {
            params: { path: { job_id: jobId }, query: { since: seen.current.results } },
          }),
        );
        if (cancelled) return;
        absorbRef.current(next);
        if (next.state === "running") timer = setTimeout(() => void poll(), POLL_MS);
      } catch (caught) {
        if (!cancelled) setError(asApiError(caught));
      }
    };
    timer = setTimeout(() => void poll(), POLL_MS);
    return () => {
      cancelled = true;
      clearTimeout(timer);
    };
  }, [jobId]);

  async function start(): Promise<void> {
    setError(null);
    try {
      const started = await call(
        api.POST("/api/nodes/{node}/upload-all", { params: { path: { node } } }),
      );
      seen.current = { results: 0, failed: 0 };
      absorb(started);
    } catch (caught) {
      setError(asApiError(caught));
    }
  }

  async function cancel(): Promise<void> {
    if (!job) return;
    try {
      absorb(
        await call(api.DELETE("/api/jobs/{job_id}", { params: { path: { job_id: job.id } } })),
      );
    } catch (caught) {
      setError(asApiError(caught));
    }
  }

  return (
    <div className="upload-all">
      {running ? (
        <button type="button" onClick={() => void cancel()}>
          {t("od.upload.cancel")}
        </button>
      ) : (
        <button type="button" className="primary" onClick={() => void start()}>
          {t("od.upload.uploadAll")}
        </button>
      )}
      {job && (
        <>
          <progress
            max={Math.max(job.total, 1)}
            value={job.done}
            aria-label={t("od.upload.progress")}
          />
          <span className="small" role="status">
            {job.done}/{job.total}
            {job.state !== "running" &&
              ` · ${t("od.upload.finished", { state: t(STATE_WORDS[job.state]), seconds: job.elapsed_s.toFixed(1) })}`}
            {failed > 0 && ` · ${t("od.upload.notReadable", { failed })}`}
          </span>
        </>
      )}
      <ErrorText error={error ?? job?.error ?? null} />
    </div>
  );
}
