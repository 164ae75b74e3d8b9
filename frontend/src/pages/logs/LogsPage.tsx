import { useMemo, useState, type ReactNode } from "react";

import { useAction } from "../../lib/useApi";
import { LogEventsCard } from "./LogEventsCard";
import { LogResultView } from "./LogResultView";
import { decodeLog } from "./logsApi";
import { LogUploadCard } from "./LogUploadCard";
import { RecordingCard } from "./RecordingCard";
import { parseStats } from "./logText";
import type { DecodedLog } from "./types";

/** Offline analysis of a CAN log, and recording the live bus into one. */
export function LogsPage(): ReactNode {
  const [log, setLog] = useState<File | null>(null);
  const [result, setResult] = useState<DecodedLog | null>(null);
  const stats = useMemo(() => (result ? parseStats(result.stats) : null), [result]);
  const decode = useAction(async (file: File, dcf: File | null) => {
    setLog(file);
    setResult(await decodeLog(file, dcf));
  });
  const run = (file: File, dcf: File | null = null): void => void decode.run(file, dcf);
  return (
    <section className="page logs-page">
      <header className="page-header">
        <h1>Logs</h1>
      </header>
      <LogUploadCard log={log} busy={decode.busy} error={decode.error} onDecode={run} />
      {result && stats && <LogResultView result={result} stats={stats} />}
      {result && stats && <LogEventsCard key={result.id} result={result} total={stats.events} />}
      <RecordingCard onDecode={run} />
    </section>
  );
}
