import { useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { FilePicker } from "../../components/FilePicker";
import { Spinner } from "../../components/Spinner";
import { DCF_FILE_TYPES, LOG_FILE_TYPES } from "./logsApi";

interface Props {
  /** The log being decoded or last decoded. */
  log: File | null;
  busy: boolean;
  error: ApiError | null;
  onDecode: (log: File, dcf: File | null, profiles: string) => void;
}

/** Pick a CAN log (and optionally the DCF that names its PDOs); it is decoded at once. */
export function LogUploadCard({ log, busy, error, onDecode }: Props): ReactNode {
  const [dcf, setDcf] = useState<File | null>(null);
  // which drive a node is, when the log holds no identity reads: "1=mdi-s1c, 2=kinco"
  const [profiles, setProfiles] = useState("");
  return (
    <section className="card" aria-labelledby="log-upload-heading">
      <header className="card-header">
        <h2 id="log-upload-heading">Analyse a CAN log</h2>
      </header>
      <p className="muted small">
        candump .log, Vector .asc and .blf, PCAN .trc, ASAM .mf4 or .csv. The server decodes NMT,
        heartbeats, SDO transfers, EMCYs in words, CiA 402 states and the bus load; a DCF adds the
        node&apos;s PDO mapping and names.
      </p>
      <div className="inline">
        <FilePicker
          label="Choose CAN log…"
          accept={LOG_FILE_TYPES}
          disabled={busy}
          onFile={(file) => onDecode(file, dcf, profiles)}
        />
        <FilePicker
          label="Choose DCF (optional)…"
          accept={DCF_FILE_TYPES}
          disabled={busy}
          onFile={setDcf}
        />
        <label className="inline small">
          Drives (optional)
          <input
            type="text"
            className="mono"
            placeholder="1=mdi-s1c, 2=kinco"
            title="Which drive a node is, for logs without identity reads: its alarms in words (mdi-s1c, kinco, cia402)"
            value={profiles}
            disabled={busy}
            onChange={(e) => setProfiles(e.target.value)}
          />
        </label>
        {dcf && (
          <span className="inline small">
            DCF: <span className="mono">{dcf.name}</span>
            <button type="button" className="small" onClick={() => setDcf(null)}>
              Remove
            </button>
          </span>
        )}
        {log && !busy && (
          <button type="button" onClick={() => onDecode(log, dcf, profiles)}>
            Decode {log.name} again{dcf ? " with the DCF" : ""}
          </button>
        )}
        {busy && (
          <span className="inline muted small">
            <Spinner label="Decoding" /> Decoding {log?.name ?? "the log"}…
          </span>
        )}
      </div>
      <ErrorText error={error} />
    </section>
  );
}
