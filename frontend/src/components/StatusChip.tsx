// Commissioning statuses in words and as badges: the Commission tab's steps and record, and
// each node's latest record on the Network page.
import type { ReactNode } from "react";

import type { RecordStatus, StepStatus } from "../api/commission";
import { useTranslation, type MessageKey } from "../i18n";

const STEP_STATUS: Record<StepStatus, MessageKey> = {
  to_do: "status.step.toDo",
  done: "status.step.done",
  failed: "status.step.failed",
  skipped: "status.step.skipped",
};

const RECORD_STATUS: Record<RecordStatus, MessageKey> = {
  in_progress: "status.record.inProgress",
  done: "status.record.done",
  failed: "status.record.failed",
};

/** A step's status: to do / done / failed / skipped. */
export function StepChip({ status }: { status: StepStatus }): ReactNode {
  const { t } = useTranslation();
  return <span className={`badge step-${status}`}>{t(STEP_STATUS[status])}</span>;
}

/** A record's overall status: in progress / done / failed. */
export function RecordChip({ status }: { status: RecordStatus }): ReactNode {
  const { t } = useTranslation();
  return <span className={`badge record-${status}`}>{t(RECORD_STATUS[status])}</span>;
}
