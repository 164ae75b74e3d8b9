import { useState, type ReactNode } from "react";

import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { useAction } from "../../lib/useApi";
import { exportPdos, type ExportFormat } from "./pdoApi";

const FORMATS: Record<ExportFormat, { label: string; title: string; file: string }> = {
  dcf: { label: "DCF fragment", title: "DCF fragment", file: "pdos.dcf" },
  python: { label: "python-canopen snippet", title: "python-canopen snippet", file: "pdos.py" },
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
  const [shown, setShown] = useState<{ format: ExportFormat; text: string } | null>(null);
  const fetchText = useAction(async (format: ExportFormat) => {
    setShown({ format, text: await exportPdos(node, format) });
  });
  const meta = shown ? FORMATS[shown.format] : null;
  const fileName = meta ? `node${node}-${meta.file}` : "";
  return (
    <>
      <span className="muted small">Export:</span>
      {(Object.keys(FORMATS) as ExportFormat[]).map((format) => (
        <button
          key={format}
          type="button"
          disabled={fetchText.busy}
          onClick={() => void fetchText.run(format)}
        >
          {FORMATS[format].label}
        </button>
      ))}
      <ErrorText error={fetchText.error} inline />
      {shown && meta && (
        <Dialog
          title={`Node ${node}: ${meta.title}`}
          onClose={() => setShown(null)}
          actions={
            <>
              <button type="button" onClick={() => setShown(null)}>
                Close
              </button>
              <button
                type="button"
                className="primary"
                onClick={() => download(shown.text, fileName)}
              >
                Download {fileName}
              </button>
            </>
          }
        >
          <textarea
            readOnly
            rows={18}
            aria-label={meta.title}
            className="pdo-export"
            value={shown.text}
          />
        </Dialog>
      )}
    </>
  );
}
