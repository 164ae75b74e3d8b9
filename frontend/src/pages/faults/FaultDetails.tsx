import type { ReactNode } from "react";

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
  const parts = checkParts(fault.check);
  return (
    <dl className="facts fault-facts">
      <dt>Code</dt>
      <dd>
        <span className="mono">{faultCode(fault)}</span>
        {fault.code_hex !== faultCode(fault) && (
          <span className="muted small"> ({fault.code_hex})</span>
        )}
      </dd>
      <dt>Meaning</dt>
      <dd>
        <span className="fault-name-en">{fault.name_en}</span>
        {fault.name_zh && (
          <span className="fault-name-zh" lang="zh">
            {fault.name_zh}
          </span>
        )}
      </dd>
      <dt>Decoded from</dt>
      <dd>{sourceLabel(fault.source)}</dd>
      {parts.length > 0 && (
        <>
          <dt>What to check</dt>
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
      <dt>Error register 1001h</dt>
      <dd>
        {fault.error_register == null ? (
          <span className="muted">not in this drive&apos;s EMCY</span>
        ) : (
          errorRegisterText(fault.error_register)
        )}
      </dd>
      {fault.manufacturer_hex && (
        <>
          <dt>Manufacturer bytes</dt>
          <dd className="mono">{fault.manufacturer_hex}</dd>
        </>
      )}
      <dt>EMCY data</dt>
      <dd className="mono">{fault.raw_hex || "—"}</dd>
      <dt>Received</dt>
      <dd>{formatDateTime(fault.time)}</dd>
      {(fault.state_before ?? fault.state_after) && (
        <>
          <dt>Drive state</dt>
          <dd>{stateChange(fault)}</dd>
        </>
      )}
    </dl>
  );
}
