import type { ReactNode } from "react";

import { currentLanguage, useTranslation } from "../../i18n";
import {
  checkParts,
  errorRegisterText,
  faultCheckParts,
  faultCode,
  formatDateTime,
  isTranslatedName,
  nameSource,
  showsChineseName,
  sourceLabel,
  stateChange,
} from "../../lib/faultText";
import type { Fault } from "./types";

/** The fault's name: in Chinese the Chinese first and the source's English beside it, a name
 * ServoDesk translated marked as such (its title names the English source); in English the
 * English first, the manual's own Chinese beside it. */
function FaultNames({ fault }: { fault: Fault }): ReactNode {
  const { t } = useTranslation();
  const chinese = currentLanguage() === "zh-CN";
  const zh = showsChineseName(fault, chinese ? "zh-CN" : "en") ? fault.name_zh : null;
  if (!chinese || !zh) {
    return (
      <>
        <span className="fault-name-en">{fault.name_en}</span>
        {zh && (
          <span className="fault-name-zh" lang="zh">
            {zh}
          </span>
        )}
      </>
    );
  }
  return (
    <>
      <span className="fault-name-first" lang="zh">
        {zh}
      </span>
      {isTranslatedName(fault) && (
        <span
          className="badge fault-name-translation"
          title={t("faults.details.translationTitle", { source: nameSource(fault) })}
        >
          {t("faults.details.translation")}
        </span>
      )}
    </>
  );
}

/** The source's own words (the manual's English, a CiA table's text) under a fold: kept beside
 * a Chinese text so the engineer can compare it with the manual at hand. */
function SourceWords({ fault }: { fault: Fault }): ReactNode {
  const { t } = useTranslation();
  return (
    <details className="fault-source-words">
      <summary>{t("faults.details.sourceWords")}</summary>
      <p lang="en" className="fault-name-source">
        {fault.name_en}
      </p>
      <ul className="fault-check" lang="en">
        {checkParts(fault.check).map((part, i) => (
          <li key={i}>
            {part.label && <strong>{part.label}: </strong>}
            {part.text}
          </li>
        ))}
      </ul>
    </details>
  );
}

/** One fault in words: names, source layer, what to check, error register, raw bytes. */
export function FaultDetails({ fault }: { fault: Fault }): ReactNode {
  const { t } = useTranslation();
  const chinese = currentLanguage() === "zh-CN";
  const parts = faultCheckParts(fault);
  const colon = chinese && fault.check_zh ? "：" : ": ";
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
        <FaultNames fault={fault} />
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
                  {part.label && (
                    <strong>
                      {part.label}
                      {colon}
                    </strong>
                  )}
                  {part.text}
                </li>
              ))}
            </ul>
          </dd>
        </>
      )}
      {chinese && (fault.name_zh ?? fault.check_zh) && (
        <>
          <dt>{t("faults.details.source")}</dt>
          <dd>
            <SourceWords fault={fault} />
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
