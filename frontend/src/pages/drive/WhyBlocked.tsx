import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import { ErrorText } from "../../components/ErrorText";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import type { EnableBlockedError } from "./driveApi";

const NMT_CODES: ReadonlySet<string> = new Set(["nmt_stopped", "nmt_not_operational"]);

/** The answer to "Why won't it enable?": each reason in words, and the way out where the tool
 * has one (an NMT state the drive does not enable in → start the node). */
export function WhyBlocked({
  node,
  blocked,
  onRetry,
  title = "Why won't it enable?",
  retry = "enable",
}: {
  node: number;
  blocked: EnableBlockedError;
  onRetry: () => void;
  /** The question answered: "Why won't it enable?", "Why didn't Shutdown happen?" … */
  title?: string;
  /** What the NMT way out does after starting the node ("enable", "send Shutdown again"). */
  retry?: string;
}): ReactNode {
  const start = useAction(async () => {
    await call(
      api.POST("/api/nodes/{node}/nmt", { params: { path: { node } }, body: { command: "start" } }),
    );
    onRetry();
  });
  const configure = useMay("configure");
  const nmt = blocked.reasons.some((r) => NMT_CODES.has(r.code));
  return (
    <section className="why-blocked" role="alert" aria-labelledby="why-blocked-heading">
      <h3 id="why-blocked-heading">{title}</h3>
      {blocked.reasons.length === 0 ? (
        <p>{blocked.message}</p>
      ) : (
        <ul>
          {blocked.reasons.map((reason) => (
            <li key={`${reason.code}:${reason.message}`} data-code={reason.code}>
              {reason.message}
            </li>
          ))}
        </ul>
      )}
      {nmt && (
        <div className="button-row">
          <button
            type="button"
            onClick={() => void start.run()}
            {...configure.gate("start the node", { disabled: start.busy })}
          >
            Start node {node} (NMT Operational) and {retry}
          </button>
          <ErrorText error={start.error} inline />
        </div>
      )}
    </section>
  );
}
