import { useState, type ReactNode } from "react";

import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { type MessageKey, useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { exportPdos, type ExportFormat } from "./pdoApi";

const FORMATS: Record<ExportFormat, { label: MessageKey; file: string }> = {
  dcf: { label: "pdo.export.dcf", file: "pdos.dcf" },
  python: { label: "pdo.export.python", file: "pdos.py" },
};

function download(text: string, name: string): void {
  const url = URL.createObjectURL(new Blob([text], { type: "text/plain" }));
  const link = document.createElement("a");
  link.href = url;
  link.download = name;
  link.click();
  setTimeout(() => URL.revokeObjectURL(url), 0);
}

/** The device's PDO configuration as a DCF fragment or a python-canopen snippet. */
export function ExportButtons({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const [shown, setShown] = useState<{ format: ExportFormat; text: string } | null>(null);
  const fetchText = useAction(async (format: ExportFormat) => {
    setShown({ format, text: await exportPdos(node, format) });
  });
  const meta = shown ? FORMATS[shown.format] : null;
  const fileName = meta ? `node${node}-${meta.file}` : "";
  return (
    <>
      <span className="muted small">{t("pdo.export.label")}</span>
      {(Object.keys(FORMATS) as ExportFormat[]).map((format) => (
        <button
          key={format}
          type="button"
          disabled={fetchText.busy}
          onClick={() => void fetchText.run(format)}
        >
          {t(FORMATS[format].label)}
        </button>
      ))}
      <ErrorText error={fetchText.error} inline />
      {shown && meta && (
        <Dialog
          title={t("pdo.export.title", { node, what: t(meta.label) })}
          onClose={() => setShown(null)}
          actions={
            <>
              <button type="button" onClick={() => setShown(null)}>
                {t("pdo.export.close")}
              </button>
              <button
                type="button"
                className="primary"
                onClick={() => download(shown.text, fileName)}
              >
                {t("pdo.export.download", { file: fileName })}
              </button>
            </>
          }
        >
          <textarea
            readOnly
            rows={18}
            aria-label={t(meta.label)}
            className="pdo-export"
            value={shown.text}
          />
        </Dialog>
      )}
    </>
  );
}
