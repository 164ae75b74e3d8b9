import { Fragment, useId, useState, type ReactNode } from "react";

import { LoadBar } from "../../components/LoadBar";
import { useTranslation } from "../../i18n";
import { formatBitrate } from "../../lib/format";
import { formatCobId, formatPercent, formatRate, pdoLabel } from "./model";
import type { BusLoad, LoadSettings } from "./types";

/** A number input that keeps what is typed and hands on only values in range. */
function SettingInput({
  label,
  unit,
  initial,
  ok,
  onValue,
  title,
}: {
  label: string;
  unit: string;
  title?: string;
  initial: number;
  ok: (value: number) => boolean;
  onValue: (value: number) => void;
}): ReactNode {
  const id = useId();
  const [text, setText] = useState(String(initial));
  const valid = (t: string): boolean => t.trim() !== "" && ok(Number(t));
  return (
    <span className="inline pdo-setting">
      <label htmlFor={id} className="small">
        {label}
      </label>
      <input
        id={id}
        className="tiny"
        type="number"
        title={title}
        value={text}
        aria-invalid={!valid(text)}
        onChange={(e) => {
          setText(e.target.value);
          if (valid(e.target.value)) onValue(Number(e.target.value));
        }}
      />
      <span className="small">{unit}</span>
    </span>
  );
}

/** The bus load the mapping will cause: total and per node, and how each PDO was counted.
 * The server counts with the settings here (warning threshold, the master's cycle for
 * event-driven RPDOs) and says whether the load is too high. */
export function BusLoadView({
  load,
  node,
  title,
  open,
  settings,
  onSettings,
}: {
  load: BusLoad;
  /** The node this page is about: its PDOs are listed. */
  node: number;
  title: string;
  /** Show how each PDO was counted without a click (a draft's load). */
  open: boolean;
  settings: LoadSettings;
  onSettings: (settings: LoadSettings) => void;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const threshold = load.threshold_percent;
  const mine = load.nodes.find((n) => n.node === node);
  return (
    <section className="card pdo-load" aria-labelledby={`${id}-h`} data-testid="bus-load">
      <header className="card-header">
        <h2 id={`${id}-h`}>{title}</h2>
        <span className="muted small">
          {formatBitrate(load.bitrate)}
          {" · "}
          {load.sync_period_us
            ? t("pdo.load.syncEvery", { ms: load.sync_period_us / 1000 })
            : t("pdo.load.noSync")}
        </span>
        <span className="spacer" />
        <SettingInput
          label={t("pdo.load.masterCycle")}
          unit="ms"
          title={t("pdo.load.masterCycleTitle")}
          initial={settings.masterPeriodMs}
          ok={(ms) => ms > 0 && ms <= 10_000}
          onValue={(masterPeriodMs) => onSettings({ ...settings, masterPeriodMs })}
        />
        <SettingInput
          label={t("pdo.load.warnAbove")}
          unit="%"
          initial={settings.threshold}
          ok={(percent) => percent >= 1 && percent <= 100}
          onValue={(percent) => onSettings({ ...settings, threshold: percent })}
        />
      </header>
      {load.over_threshold && (
        <p className="warning" role="alert">
          {t("pdo.load.overThreshold", { percent: formatPercent(load.percent), threshold })}
        </p>
      )}
      <div className="load-rows">
        <span>{t("pdo.load.allNodes")}</span>
        <LoadBar percent={load.percent} threshold={threshold} label={t("pdo.load.total")} />
        <span className="muted small num">{Math.round(load.total_bits_per_s)} bit/s</span>
        {load.nodes.map((n) => (
          <Fragment key={n.node}>
            <span>{t("pdo.load.node", { node: n.node })}</span>
            <LoadBar
              percent={n.percent}
              threshold={threshold}
              label={t("pdo.load.nodeLoad", { node: n.node })}
            />
            <span className="muted small num">{Math.round(n.bits_per_s)} bit/s</span>
          </Fragment>
        ))}
      </div>
      {mine && mine.pdos.length > 0 && (
        <details className="pdo-load-details" open={open}>
          <summary>{t("pdo.load.howCounted", { node })}</summary>
          <table className="data-table pdo-load-table">
            <thead>
              <tr>
                <th>PDO</th>
                <th>COB-ID</th>
                <th>{t("pdo.load.frames")}</th>
                <th>{t("pdo.load.bitsPerFrame")}</th>
                <th>{t("pdo.load.load")}</th>
                <th>{t("pdo.load.countedAs")}</th>
              </tr>
            </thead>
            <tbody>
              {mine.pdos.map((p) => (
                <tr key={`${p.kind}${p.number}`}>
                  <th>{pdoLabel(p)}</th>
                  <td className="mono">{formatCobId(p.cob_id)}</td>
                  <td className="num">{formatRate(p.frames_per_s)}</td>
                  <td className="num">{p.bits_per_frame}</td>
                  <td className="num">{Math.round(p.bits_per_s)} bit/s</td>
                  <td className="small">{p.basis}</td>
                </tr>
              ))}
            </tbody>
          </table>
        </details>
      )}
      {load.notes.length > 0 && (
        <details className="pdo-load-details">
          <summary>{t("pdo.load.notes", { count: load.notes.length })}</summary>
          <ul className="muted small pdo-notes">
            {load.notes.map((note, i) => (
              <li key={i}>{note}</li>
            ))}
          </ul>
        </details>
      )}
    </section>
  );
}
