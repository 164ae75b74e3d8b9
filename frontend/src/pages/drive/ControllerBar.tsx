import type { ReactNode } from "react";

import { takeControl } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
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
  const operate = useMay("operate");
  const take = useAction(async (takeOver: boolean) => show(await takeControl(node, takeOver)));
  if (!controller) return <span className="muted small">Control: …</span>;
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
          ? "You control this drive"
          : other
            ? `Controlled by ${holder.name ?? holder.client_id}`
            : "Nobody controls this drive"}
      </span>
      {other && (
        <button
          type="button"
          className="small"
          onClick={() => void take.run(true)}
          {...operate.gate("take control of the drive", {
            disabled: take.busy,
            title: "Their jogs stop; your commands pass from now on",
          })}
        >
          Take over
        </button>
      )}
      {!holder && (
        <button
          type="button"
          className="small"
          onClick={() => void take.run(false)}
          {...operate.gate("take control of the drive", { disabled: take.busy })}
        >
          Take control
        </button>
      )}
      <span
        className={`badge ${protection.active ? "drive-ok" : "drive-warn"}`}
        title={protection.message}
        data-testid="heartbeat-protection"
      >
        Heartbeat protection {protection.active ? `on (${protection.consumer_ms} ms)` : "off"}
      </span>
      <ErrorText error={take.error} inline />
    </span>
  );
}
