import type { ReactNode } from "react";

import { RECORD_STATUS_TEXT, STEP_STATUS_TEXT } from "./steps";
import type { RecordStatus, StepStatus } from "./types";

/** A step's status: to do / done / failed / skipped. */
export function StepChip({ status }: { status: StepStatus }): ReactNode {
  return <span className={`badge step-${status}`}>{STEP_STATUS_TEXT[status]}</span>;
}

/** A record's overall status: in progress / done / failed. */
export function RecordChip({ status }: { status: RecordStatus }): ReactNode {
  return <span className={`badge record-${status}`}>{RECORD_STATUS_TEXT[status]}</span>;
}
