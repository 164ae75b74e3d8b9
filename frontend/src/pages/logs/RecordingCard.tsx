import { useState, type ReactNode } from "react";

import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { Trans, useTranslation } from "../../i18n";
import { formatCount } from "../../lib/format";
import { useAction, useApi } from "../../lib/useApi";
import { usePoll } from "../../lib/usePoll";
import { useMay } from "../../session/context";
import {
  recordingStatus,
  saveBlob,
  startRecording,
  stopRecording,
  type RecordedFile,
} from "./logsApi";
import { recordingText } from "./logText";
import type { RecordingFormat } from "./types";

const FORMATS: { format: RecordingFormat; label: string }[] = [
  { format: "blf", label: "Vector BLF (.blf)" },
  { format: "asc", label: "Vector ASC (.asc)" },
  { format: "log", label: "candump (.log)" },
  { format: "mf4", label: "ASAM MDF 4 (.mf4)" },
];

/** Raw frames of the live bus into a file: start, watch it grow, stop and download. */
export function RecordingCard({ onDecode }: { onDecode: (file: File) => void }): ReactNode {
  const { t } = useTranslation();
  const status = useApi((signal) => recordingStatus(signal), "recording");
  const active = status.data?.active ?? false;
  // the clock for the duration moves with each poll, not with each render
  const [now, setNow] = useState(() => Date.now() / 1000);
  usePoll(
    () => {
      status.reload();
      setNow(Date.now() / 1000);
    },
    1000,
    active,
  );
  const [format, setFormat] = useState<RecordingFormat>("blf");
  const operate = useMay("operate");
  const [file, setFile] = useState<RecordedFile | null>(null);
  const start = useAction(async () => {
    setFile(null);
    const answer = await startRecording(format);
    status.setData(() => answer);
    setNow(Date.now() / 1000);
  });
  const stop = useAction(async () => {
    const recorded = await stopRecording(`recording.${status.data?.format ?? format}`);
    setFile(recorded);
    saveBlob(recorded.blob, recorded.name);
    status.reload();
  });
  const data = status.data;
  return (
    <section className="card" aria-labelledby="recording-heading">
      <header className="card-header">
        <h2 id="recording-heading">{t("logs.page.recording.heading")}</h2>
        {data && (
          <span className={`badge${active ? " recording-on" : ""}`} role="status">
            {recordingText(data, now)}
          </span>
        )}
      </header>
      <div className="inline">
        <label htmlFor="recording-format" className="muted">
          {t("logs.page.recording.format")}
        </label>
        <select
          id="recording-format"
          value={format}
          disabled={active}
          onChange={(e) => setFormat(e.target.value as RecordingFormat)}
        >
          {FORMATS.map((f) => (
            <option key={f.format} value={f.format}>
              {f.label}
            </option>
          ))}
        </select>
        {active ? (
          <button
            type="button"
            className="primary"
            {...operate.gate(t("logs.page.recording.gateStop"), { disabled: stop.busy })}
            onClick={() => void stop.run()}
          >
            {t("logs.page.recording.stop")}
          </button>
        ) : (
          <button
            type="button"
            className="primary"
            {...operate.gate(t("logs.page.recording.gateStart"), { disabled: start.busy || !data })}
            onClick={() => void start.run()}
          >
            {t("logs.page.recording.start")}
          </button>
        )}
        {(start.busy || stop.busy) && <Spinner />}
      </div>
      <ErrorText error={status.data ? null : status.error} onRetry={status.reload} />
      <ErrorText error={start.error ?? stop.error} />
      {file && (
        <p className="inline small">
          <span>
            <Trans
              i18nKey="logs.page.recording.saved"
              values={{ name: file.name, size: formatCount(file.blob.size) }}
              components={{ name: <span className="mono" /> }}
            />
          </span>
          <button type="button" className="small" onClick={() => saveBlob(file.blob, file.name)}>
            {t("logs.page.recording.downloadAgain")}
          </button>
          <button
            type="button"
            className="small"
            onClick={() => onDecode(new File([file.blob], file.name))}
          >
            {t("logs.page.recording.analyse")}
          </button>
        </p>
      )}
    </section>
  );
}
