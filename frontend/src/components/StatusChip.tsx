// Commissioning statuses in words and as badges: the Commission tab's steps and record, and
// each node's latest record on the Network page.
import type { ReactNode } from "react";

import type { RecordStatus, StepStatus } from "../api/commission";

const STEP_STATUS_TEXT: Record<StepStatus, string> = {
  to_do: "To do",
  done: "Done",
  failed: "Failed",
  skipped: "Skipped",
};

export const RECORD_STATUS_TEXT: Record<RecordStatus, string> = {
  in_progress: "In progress",
  done: "Done",
  failed: "Failed",
};

/** A step's status: to do / done / failed / skipped. */
export function StepChip({ status }: { status: StepStatus }): ReactNode {
  return <span className={`badge step-${status}`}>{STEP_STATUS_TEXT[status]}</span>;
}

/** A record's overall status: in progress / done / failed. */
export function RecordChip({ status }: { status: RecordStatus }): ReactNode {
  return <span className={`badge record-${status}`}>{RECORD_STATUS_TEXT[status]}</span>;
}
