import { useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { FilePicker } from "../../components/FilePicker";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
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
  const { t } = useTranslation();
  const [dcf, setDcf] = useState<File | null>(null);
  // which drive a node is, when the log holds no identity reads: "1=mdi-s1c, 2=kinco"
  const [profiles, setProfiles] = useState("");
  return (
    <section className="card" aria-labelledby="log-upload-heading">
      <header className="card-header">
        <h2 id="log-upload-heading">{t("logs.page.upload.heading")}</h2>
      </header>
      <p className="muted small">{t("logs.page.upload.intro")}</p>
      <div className="inline">
        <FilePicker
          label={t("logs.page.upload.chooseLog")}
          accept={LOG_FILE_TYPES}
          disabled={busy}
          onFile={(file) => onDecode(file, dcf, profiles)}
        />
        <FilePicker
          label={t("logs.page.upload.chooseDcf")}
          accept={DCF_FILE_TYPES}
          disabled={busy}
          onFile={setDcf}
        />
        <label className="inline small">
          {t("logs.page.upload.drives")}
          <input
            type="text"
            className="mono"
            placeholder="1=mdi-s1c, 2=kinco"
            title={t("logs.page.upload.drivesTitle")}
            value={profiles}
            disabled={busy}
            onChange={(e) => setProfiles(e.target.value)}
          />
        </label>
        {dcf && (
          <span className="inline small">
            {t("logs.page.upload.dcf")} <span className="mono">{dcf.name}</span>
            <button type="button" className="small" onClick={() => setDcf(null)}>
              {t("logs.page.upload.remove")}
            </button>
          </span>
        )}
        {log && !busy && (
          <button type="button" onClick={() => onDecode(log, dcf, profiles)}>
            {dcf
              ? t("logs.page.upload.againWithDcf", { name: log.name })
              : t("logs.page.upload.again", { name: log.name })}
          </button>
        )}
        {busy && (
          <span className="inline muted small">
            <Spinner label={t("logs.page.upload.decoding")} />{" "}
            {log
              ? t("logs.page.upload.decodingName", { name: log.name })
              : t("logs.page.upload.decodingLog")}
          </span>
        )}
      </div>
      <ErrorText error={error} />
    </section>
  );
}
