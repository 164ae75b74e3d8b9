import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import type { EnableBlockedError } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { useTranslation } from "../../i18n";
import { serverText } from "../../lib/serverText";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";

const NMT_CODES: ReadonlySet<string> = new Set(["nmt_stopped", "nmt_not_operational"]);

/** The answer to "Why won't it enable?": each reason in words, and the way out where the tool
 * has one (an NMT state the drive does not enable in → start the node; an active fault → reset
 * it, then enable: two requests, never one enable that resets behind the user's back). */
export function WhyBlocked({
  node,
  blocked,
  onRetry,
  onResetFault,
  title,
  retry,
}: {
  node: number;
  blocked: EnableBlockedError;
  onRetry: () => void;
  /** Offered when a fault blocks: fault reset, then enable. */
  onResetFault?: () => void;
  /** The question answered: "Why won't it enable?", "Why didn't Shutdown happen?" … */
  title?: string;
  /** What the NMT way out does after starting the node ("enable", "send Shutdown again"). */
  retry?: string;
}): ReactNode {
  const { t } = useTranslation();
  const start = useAction(async () => {
    await call(
      api.POST("/api/nodes/{node}/nmt", { params: { path: { node } }, body: { command: "start" } }),
    );
    onRetry();
  });
  const configure = useMay("configure");
  const nmt = blocked.reasons.some((r) => NMT_CODES.has(r.code));
  const fault = blocked.reasons.some((r) => r.code === "fault");
  return (
    <section className="why-blocked" role="alert" aria-labelledby="why-blocked-heading">
      <h3 id="why-blocked-heading">{title ?? t("drive.controls.whyEnable")}</h3>
      {blocked.reasons.length === 0 ? (
        <p>{blocked.message}</p>
      ) : (
        <ul>
          {blocked.reasons.map((reason) => (
            <li key={`${reason.code}:${reason.message}`} data-code={reason.code}>
              {serverText(reason)}
            </li>
          ))}
        </ul>
      )}
      {nmt && (
        <div className="button-row">
          <button
            type="button"
            onClick={() => void start.run()}
            {...configure.gate(t("drive.why.gateStart"), { disabled: start.busy })}
          >
            {t("drive.why.startNode", { node, retry: retry ?? t("drive.controls.enableVerb") })}
          </button>
          <ErrorText error={start.error} inline />
        </div>
      )}
      {fault && onResetFault && (
        <div className="button-row">
          <button type="button" onClick={onResetFault} title={t("drive.why.resetTitle")}>
            {t("drive.why.reset")}
          </button>
          <span className="muted small">{t("drive.why.resetWhen")}</span>
        </div>
      )}
    </section>
  );
}
