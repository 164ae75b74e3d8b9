import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import {
  checkParts,
  errorRegisterText,
  faultCode,
  formatDateTime,
  sourceLabel,
  stateChange,
} from "../../lib/faultText";
import type { Fault } from "./types";

/** One fault in words: names, source layer, what to check, error register, raw bytes. */
export function FaultDetails({ fault }: { fault: Fault }): ReactNode {
  const { t } = useTranslation();
  const parts = checkParts(fault.check);
  return (
    <dl className="facts fault-facts">
      <dt>{t("faults.details.code")}</dt>
      <dd>
        <span className="mono">{faultCode(fault)}</span>
        {fault.code_hex !== faultCode(fault) && (
          <span className="muted small"> ({fault.code_hex})</span>
        )}
      </dd>
      <dt>{t("faults.details.meaning")}</dt>
      <dd>
        <span className="fault-name-en">{fault.name_en}</span>
        {fault.name_zh && (
          <span className="fault-name-zh" lang="zh">
            {fault.name_zh}
          </span>
        )}
      </dd>
      <dt>{t("faults.details.decodedFrom")}</dt>
      <dd>{sourceLabel(fault.source)}</dd>
      {parts.length > 0 && (
        <>
          <dt>{t("faults.details.whatToCheck")}</dt>
          <dd>
            <ul className="fault-check">
              {parts.map((part, i) => (
                <li key={i}>
                  {part.label && <strong>{part.label}: </strong>}
                  {part.text}
                </li>
              ))}
            </ul>
          </dd>
        </>
      )}
      <dt>{t("faults.details.errorRegister")}</dt>
      <dd>
        {fault.error_register == null ? (
          <span className="muted">{t("faults.details.notInEmcy")}</span>
        ) : (
          errorRegisterText(fault.error_register)
        )}
      </dd>
      {fault.manufacturer_hex && (
        <>
          <dt>{t("faults.details.manufacturerBytes")}</dt>
          <dd className="mono">{fault.manufacturer_hex}</dd>
        </>
      )}
      <dt>{t("faults.details.emcyData")}</dt>
      <dd className="mono">{fault.raw_hex || "—"}</dd>
      <dt>{t("faults.details.received")}</dt>
      <dd>{formatDateTime(fault.time)}</dd>
      {(fault.state_before ?? fault.state_after) && (
        <>
          <dt>{t("faults.details.driveState")}</dt>
          <dd>{stateChange(fault)}</dd>
        </>
      )}
    </dl>
  );
}
