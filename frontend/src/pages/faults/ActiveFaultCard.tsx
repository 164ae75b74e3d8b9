import { useState, type ReactNode } from "react";

import { Link } from "react-router";

import { HeldByOtherError } from "../../api/driveApi";
import { errorCode, resetFault } from "../../api/faultsApi";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { Trans, useTranslation } from "../../i18n";
import { errorCodeParts, faultCode, faultName } from "../../lib/faultText";
import { serverText } from "../../lib/serverText";
import { useThrottled } from "../../lib/useThrottled";
import { useAction, useApi } from "../../lib/useApi";
import { useLiveStore } from "../../live/context";
import { nodeUrl } from "../../nav/paths";
import { useMay } from "../../session/context";
import { FaultDetails } from "./FaultDetails";
import type { Fault } from "./types";

function ErrorCodeValue({ hex, words }: { hex: string; words: string | null }): ReactNode {
  return (
    <>
      <span className="mono">{hex}</span>
      {words && `: ${words}`}
    </>
  );
}

/** 603Fh is read again at most this often while the active fault keeps changing (a storm). */
export const ERROR_CODE_READ_MS = 1000;

/** 603Fh as the drive reports it now, tied to the active fault when the codes agree. The live
 * channel does not carry it: it is read by SDO when the active fault's code changes. */
function ErrorCodeLine({
  node,
  active,
}: {
  node: number;
  active: Fault | null | undefined;
}): ReactNode {
  const { t } = useTranslation();
  // read again when the active fault's code changes (not for each EMCY of the same fault)
  const version = useThrottled(active ? String(active.code) : String(active), ERROR_CODE_READ_MS);
  const code = useApi((signal) => errorCode(node, signal), `603f-${node}-${version}`);
  return (
    <p className="small error-code-line">
      <span className="muted">{t("faults.active.errorCode")}</span>
      {code.data ? (
        <ErrorCodeValue {...errorCodeParts(code.data.value, active)} />
      ) : code.error ? (
        <ErrorText error={code.error} inline />
      ) : (
        <Spinner label={t("faults.active.reading603F")} />
      )}
    </p>
  );
}

/** The fault the node is in now, in words, with the reset and what it did. A reset's answer
 * goes to the live store (unless the channel told newer), where `active` comes from. */
export function ActiveFaultCard({
  node,
  active,
}: {
  node: number;
  active: Fault | null | undefined;
}): ReactNode {
  const { t } = useTranslation();
  const store = useLiveStore();
  const [result, setResult] = useState<string | null>(null);
  const operate = useMay("operate");
  const reset = useAction(async () => {
    setResult(null);
    const version = store.faultVersion();
    const answer = await resetFault(node);
    store.setNodeFault(node, answer.active, version);
    setResult(
      answer.ok ? serverText(answer) : t("faults.active.notReset", { message: serverText(answer) }),
    );
  });
  return (
    <section
      className={`card fault-active${active ? " in-fault" : ""}`}
      aria-labelledby="fault-active-heading"
    >
      <header className="card-header">
        <h2 id="fault-active-heading">
          {active === undefined
            ? t("faults.active.heading")
            : active
              ? t("faults.active.inFault", { code: faultCode(active), name: faultName(active) })
              : t("faults.active.none")}
        </h2>
        <span className="spacer" />
        <button
          type="button"
          className={active ? "primary" : undefined}
          {...operate.gate(t("faults.active.gateReset"), { disabled: reset.busy })}
          onClick={() => void reset.run()}
        >
          {t("faults.active.reset")}
        </button>
        {reset.busy && <Spinner label={t("faults.active.resetting")} />}
      </header>
      {result && (
        <p className="note" role="status">
          {result}
        </p>
      )}
      {reset.error instanceof HeldByOtherError ? (
        <p className="error" role="alert">
          <Trans
            i18nKey="faults.active.heldByOther"
            values={{
              node,
              holder:
                reset.error.holder?.name ??
                reset.error.holder?.client_id ??
                t("faults.active.anotherClient"),
            }}
            components={{ page: <Link to={nodeUrl(node, "drive")} /> }}
          />
        </p>
      ) : (
        <ErrorText error={reset.error} />
      )}
      {active ? (
        <FaultDetails fault={active} />
      ) : (
        active === null && <p className="muted">{t("faults.active.noFault")}</p>
      )}
      <ErrorCodeLine node={node} active={active} />
    </section>
  );
}
