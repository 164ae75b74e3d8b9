import { useCallback, useState, type ReactNode } from "react";

import { getRecord, listRecords } from "../../api/commissionApi";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useApi } from "../../lib/useApi";
import { RecordHeader } from "./RecordHeader";
import { DEFAULT_RUN_SETTINGS, type RunSettings } from "./RunInputs";
import { StartForm } from "./StartForm";
import { StepItem } from "./StepItem";
import { orderedSteps } from "./steps";
import type { CommissioningRecord, CommissioningStep, StepKey } from "./types";

/** The guided, resumable commissioning flow of one axis: start a record or resume the latest,
 * run or sign off its nine steps in order, open the hand-over report. */
export function CommissionPage({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const records = useApi((signal) => listRecords(node, signal), `commission-list-${node}`);
  const [chosen, setChosen] = useState<number | null>(null);
  const [starting, setStarting] = useState(false);
  const [running, setRunning] = useState<StepKey | null>(null);
  const [settings, setSettings] = useState<RunSettings>(DEFAULT_RUN_SETTINGS);

  const list = records.data ?? [];
  // The chosen record if it is this node's, else the newest (the list is newest first).
  const id = list.find((r) => r.id === chosen)?.id ?? list[0]?.id ?? null;
  const record = useApi(
    (signal): Promise<CommissioningRecord | null> =>
      id === null ? Promise.resolve(null) : getRecord(id, signal),
    `commission-record-${node}-${id ?? "none"}`,
  );
  const { setData, reload: reloadRecord } = record;
  const reloadList = records.reload;

  const onChanged = useCallback(
    (step: CommissioningStep | null) => {
      if (step) {
        setData((old) =>
          old ? { ...old, steps: old.steps.map((s) => (s.key === step.key ? step : s)) } : old,
        );
      }
      // The overall status is the server's to say.
      reloadRecord();
      reloadList();
    },
    [setData, reloadRecord, reloadList],
  );

  function started(created: CommissioningRecord): void {
    setStarting(false);
    setChosen(created.id);
    reloadList();
  }

  const current = record.data ?? null;
  const showStart = starting || (records.data !== undefined && list.length === 0);
  return (
    <div className="commission-page">
      <ErrorText error={records.data ? null : records.error} onRetry={records.reload} />
      {records.data === undefined && !records.error && (
        <Spinner label={t("commission.page.loading")} />
      )}
      {showStart && (
        <StartForm
          node={node}
          onStarted={started}
          onCancel={list.length > 0 ? () => setStarting(false) : undefined}
        />
      )}
      {!showStart && current && (
        <>
          <RecordHeader
            record={current}
            records={list}
            onChoose={setChosen}
            onNew={() => setStarting(true)}
          />
          <ErrorText error={record.error} onRetry={record.reload} />
          <ol className="step-list" aria-label={t("commission.page.steps")}>
            {orderedSteps(current).map((step, i) => (
              <StepItem
                key={`${current.id}-${step.key}`}
                node={node}
                recordId={current.id}
                index={i + 1}
                step={step}
                running={running}
                onRunning={setRunning}
                settings={settings}
                onSettings={setSettings}
                onChanged={onChanged}
              />
            ))}
          </ol>
        </>
      )}
      {!showStart && !current && record.error && (
        <ErrorText error={record.error} onRetry={record.reload} />
      )}
    </div>
  );
}
