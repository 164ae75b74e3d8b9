import type { ReactNode } from "react";
import { Link } from "react-router";

import { RecordChip } from "../../components/StatusChip";
import { nodeUrl } from "../../nav/paths";
import type { LatestRecord } from "./latestRecords";

/** A node's latest commissioning record in the node list: its status, linking to the flow. */
export function CommissionChip({
  node,
  latest,
}: {
  node: number;
  latest: LatestRecord | null | undefined;
}): ReactNode {
  if (latest === undefined) return <span className="muted">…</span>;
  if (latest === null) {
    return (
      <Link to={nodeUrl(node, "commission")} aria-label={`Commission node ${node}: no record yet`}>
        —
      </Link>
    );
  }
  return (
    <Link
      to={nodeUrl(node, "commission")}
      className="commission-chip"
      aria-label={`Commissioning of node ${node}: record #${latest.id}`}
      title={`Record #${latest.id}${latest.title ? ` ${latest.title}` : ""}: open the Commission page`}
    >
      <RecordChip status={latest.status} />
    </Link>
  );
}
