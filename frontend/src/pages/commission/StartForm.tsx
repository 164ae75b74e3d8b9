import { useState, type SubmitEvent, type ReactNode } from "react";

import { createRecord } from "../../api/commissionApi";
import { getDrive } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation, type MessageKey } from "../../i18n";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";
import type { CommissioningRecord } from "./types";

const MODE_NAMES: Record<string, MessageKey> = {
  pp: "commission.mode.pp",
  pv: "commission.mode.pv",
  pt: "commission.mode.pt",
  hm: "commission.mode.hm",
  ip: "commission.mode.ip",
  csp: "commission.mode.csp",
  csv: "commission.mode.csv",
  cst: "commission.mode.cst",
};

/** Checked at first: the modes a test move exercises, where the drive has them. */
const FIRST_PICK = ["pp", "pv"];

/** Start a record: the modes to commission (of those the drive supports, 6502h) and a title. */
export function StartForm({
  node,
  onStarted,
  onCancel,
}: {
  node: number;
  onStarted: (record: CommissioningRecord) => void;
  onCancel?: () => void;
}): ReactNode {
  const { t } = useTranslation();
  const operate = useMay("operate");
  const drive = useApi((signal) => getDrive(node, signal), `commission-drive-${node}`);
  const supported = drive.data?.supported_modes ?? [];
  const [picked, setPicked] = useState<string[] | null>(null);
  const modes = picked ?? supported.filter((m) => FIRST_PICK.includes(m));
  const [title, setTitle] = useState("");
  const start = useAction(async () => onStarted(await createRecord(node, modes, title)));

  function modeName(mode: string): string {
    const key = MODE_NAMES[mode];
    return key ? t(key) : "";
  }
  function toggle(mode: string, on: boolean): void {
    setPicked(on ? [...modes, mode] : modes.filter((m) => m !== mode));
  }
  function submit(event: SubmitEvent): void {
    event.preventDefault();
    void start.run();
  }

  return (
    <form className="card start-form" onSubmit={submit} aria-labelledby="start-heading">
      <header className="card-header">
        <h2 id="start-heading">{t("commission.start.heading", { node })}</h2>
      </header>
      <p className="muted small">{t("commission.start.intro")}</p>
      {drive.error && !drive.data && <ErrorText error={drive.error} onRetry={drive.reload} />}
      {!drive.data && !drive.error && <Spinner label={t("commission.start.readingModes")} />}
      {drive.data && (
        <fieldset className="mode-picks">
          <legend>
            {t("commission.start.modes", {
              modes: supported.length
                ? supported.join(", ").toUpperCase()
                : t("commission.start.noModes"),
            })}
          </legend>
          {supported.map((mode) => (
            <label key={mode} className="check">
              <input
                type="checkbox"
                checked={modes.includes(mode)}
                onChange={(e) => toggle(mode, e.target.checked)}
              />
              <span>
                <span className="mono">{mode.toUpperCase()}</span> {modeName(mode)}
              </span>
            </label>
          ))}
        </fieldset>
      )}
      <label className="inline">
        {t("commission.start.title")}{" "}
        <span className="muted small">{t("commission.start.optional")}</span>
        <input
          className="wide"
          value={title}
          maxLength={200}
          placeholder={t("commission.start.titlePlaceholder")}
          onChange={(e) => setTitle(e.target.value)}
        />
      </label>
      <div className="button-row">
        <button
          type="submit"
          className="primary"
          {...operate.gate(t("commission.start.gate"), {
            disabled: start.busy || !drive.data || modes.length === 0,
          })}
        >
          {t("commission.start.submit")}
        </button>
        {onCancel && (
          <button type="button" className="link-button" onClick={onCancel}>
            {t("commission.cancel")}
          </button>
        )}
        {drive.data && modes.length === 0 && (
          <span className="muted small">{t("commission.start.pickOne")}</span>
        )}
      </div>
      <ErrorText error={start.error} />
    </form>
  );
}
