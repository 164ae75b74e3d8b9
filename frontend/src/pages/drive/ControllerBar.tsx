import type { ReactNode } from "react";

import { takeControl } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import type { ControllerInfo } from "./types";

/** "Who holds control": this tab, another one (take over), or nobody; and whether the drive
 * stops by itself when the tool's heartbeat stops (1016h). */
export function ControllerBar({
  node,
  controller,
  show,
}: {
  node: number;
  controller: ControllerInfo | undefined;
  show: (info: ControllerInfo) => void;
}): ReactNode {
  const { t } = useTranslation();
  const operate = useMay("operate");
  const take = useAction(async (takeOver: boolean) => show(await takeControl(node, takeOver)));
  if (!controller) return <span className="muted small">{t("drive.controller.pending")}</span>;
  const holder = controller.holder;
  const other = holder !== null && !controller.you;
  const protection = controller.protection;
  return (
    <span className="controller-bar">
      <span
        className={`badge ${controller.you ? "drive-ok" : other ? "drive-warn" : ""}`}
        data-testid="controller"
      >
        {controller.you
          ? t("drive.controller.you")
          : other
            ? t("drive.controller.other", { name: holder.name ?? holder.client_id })
            : t("drive.controller.nobody")}
      </span>
      {other && (
        <button
          type="button"
          className="small"
          onClick={() => void take.run(true)}
          {...operate.gate(t("drive.controller.gate"), {
            disabled: take.busy,
            title: t("drive.controller.takeOverTitle"),
          })}
        >
          {t("drive.controller.takeOver")}
        </button>
      )}
      {!holder && (
        <button
          type="button"
          className="small"
          onClick={() => void take.run(false)}
          {...operate.gate(t("drive.controller.gate"), { disabled: take.busy })}
        >
          {t("drive.controller.take")}
        </button>
      )}
      <span
        className={`badge ${protection.active ? "drive-ok" : "drive-warn"}`}
        title={protection.message}
        data-testid="heartbeat-protection"
      >
        {protection.active
          ? t("drive.controller.heartbeatOn", { ms: protection.consumer_ms })
          : t("drive.controller.heartbeatOff")}
      </span>
      <ErrorText error={take.error} inline />
    </span>
  );
}
