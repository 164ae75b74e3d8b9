import type { ReactNode } from "react";
import { Link } from "react-router";

import { RecordChip } from "../../components/StatusChip";
import { useTranslation } from "../../i18n";
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
  const { t } = useTranslation();
  if (latest === undefined) return <span className="muted">…</span>;
  if (latest === null) {
    return (
      <Link to={nodeUrl(node, "commission")} aria-label={t("network.commission.none", { node })}>
        —
      </Link>
    );
  }
  return (
    <Link
      to={nodeUrl(node, "commission")}
      className="commission-chip"
      aria-label={t("network.commission.label", { node, id: latest.id })}
      title={
        latest.title
          ? t("network.commission.titleNamed", { id: latest.id, title: latest.title })
          : t("network.commission.title", { id: latest.id })
      }
    >
      <RecordChip status={latest.status} />
    </Link>
  );
}
