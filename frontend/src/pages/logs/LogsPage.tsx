import { useMemo, useState, type ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { LogEventsCard } from "./LogEventsCard";
import { LogResultView } from "./LogResultView";
import { KeptLogsCard } from "./KeptLogsCard";
import { decodeLog, openLog } from "./logsApi";
import { LogUploadCard } from "./LogUploadCard";
import { RecordingCard } from "./RecordingCard";
import { parseStats } from "./logText";
import type { DecodedLog } from "./types";

/** Offline analysis of a CAN log, and recording the live bus into one. */
export function LogsPage(): ReactNode {
  const { t } = useTranslation();
  const [log, setLog] = useState<File | null>(null);
  const [result, setResult] = useState<DecodedLog | null>(null);
  const stats = useMemo(() => (result ? parseStats(result.stats) : null), [result]);
  const [decoded, setDecoded] = useState(0); // decodes finished: the kept list reads again
  const decode = useAction(async (file: File, dcf: File | null, profiles: string) => {
    setLog(file);
    setResult(await decodeLog(file, dcf, profiles));
    setDecoded((n) => n + 1);
  });
  const reopen = useAction(async (id: string) => {
    setLog(null);
    setResult(await openLog(id));
  });
  const run = (file: File, dcf: File | null = null, profiles = ""): void =>
    void decode.run(file, dcf, profiles);
  return (
    <section className="page logs-page">
      <header className="page-header">
        <h1>{t("logs.page.heading")}</h1>
      </header>
      <LogUploadCard
        log={log}
        busy={decode.busy || reopen.busy}
        error={decode.error ?? reopen.error}
        onDecode={run}
      />
      {result && stats && <LogResultView result={result} stats={stats} />}
      {result && stats && <LogEventsCard key={result.id} result={result} total={stats.events} />}
      <KeptLogsCard
        current={result?.id ?? null}
        version={decoded}
        onOpen={(id) => void reopen.run(id)}
        onDeleted={(id) => {
          if (result?.id === id) setResult(null);
        }}
      />
      <RecordingCard onDecode={run} />
    </section>
  );
}
