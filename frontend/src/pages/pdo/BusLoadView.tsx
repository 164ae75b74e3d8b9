import { Fragment, useId, useState, type ReactNode } from "react";

import { formatBitrate } from "../../lib/format";
import { formatCobId, formatPercent, formatRate, pdoLabel } from "./model";
import type { BusLoad } from "./types";

/** A load bar: the used share, and a mark at the threshold. */
export function LoadBar({
  percent,
  threshold,
  label,
}: {
  percent: number;
  threshold: number;
  label: string;
}): ReactNode {
  const over = percent > threshold;
  return (
    <div
      className={`load-bar${over ? " over" : ""}`}
      role="meter"
      aria-label={label}
      aria-valuemin={0}
      aria-valuemax={100}
      aria-valuenow={Math.round(percent * 10) / 10}
      aria-valuetext={formatPercent(percent)}
    >
      <div className="load-fill" style={{ width: `${Math.min(100, percent)}%` }} />
      <div className="load-threshold" style={{ left: `${Math.min(100, threshold)}%` }} />
      <span className="load-text">{formatPercent(percent)}</span>
    </div>
  );
}

/** The bus load the mapping will cause: total and per node, and how each PDO was counted. */
export function BusLoadView({
  load,
  node,
  title,
  open,
  threshold,
  onThreshold,
}: {
  load: BusLoad;
  /** The node this page is about: its PDOs are listed. */
  node: number;
  title: string;
  /** Show how each PDO was counted without a click (a draft's load). */
  open: boolean;
  threshold: number;
  onThreshold: (percent: number) => void;
}): ReactNode {
  const id = useId();
  const [text, setText] = useState(String(threshold));
  const mine = load.nodes.find((n) => n.node === node);
  return (
    <section className="card pdo-load" aria-labelledby={`${id}-h`} data-testid="bus-load">
      <header className="card-header">
        <h2 id={`${id}-h`}>{title}</h2>
        <span className="muted small">
          {formatBitrate(load.bitrate)}
          {load.sync_period_us ? ` · SYNC every ${load.sync_period_us / 1000} ms` : " · no SYNC"}
        </span>
        <span className="spacer" />
        <label htmlFor={`${id}-t`} className="small">
          Warn above
        </label>
        <input
          id={`${id}-t`}
          className="tiny"
          type="number"
          min={1}
          max={100}
          value={text}
          aria-invalid={!(Number(text) >= 1 && Number(text) <= 100)}
          onChange={(e) => {
            setText(e.target.value);
            const value = Number(e.target.value);
            if (e.target.value !== "" && value >= 1 && value <= 100) onThreshold(value);
          }}
        />
        <span className="small">%</span>
      </header>
      {load.percent > threshold && (
        <p className="warning" role="alert">
          The bus would be {formatPercent(load.percent)} loaded, above {threshold} %: frames may be
          delayed. Slow down SYNC, raise inhibit times or map fewer PDOs.
        </p>
      )}
      <div className="load-rows">
        <span>All nodes</span>
        <LoadBar percent={load.percent} threshold={threshold} label="Total bus load" />
        <span className="muted small num">{Math.round(load.total_bits_per_s)} bit/s</span>
        {load.nodes.map((n) => (
          <Fragment key={n.node}>
            <span>Node {n.node}</span>
            <LoadBar percent={n.percent} threshold={threshold} label={`Node ${n.node} load`} />
            <span className="muted small num">{Math.round(n.bits_per_s)} bit/s</span>
          </Fragment>
        ))}
      </div>
      <details className="pdo-load-details" open={open}>
        <summary>
          How node {node}'s PDOs are counted
          {load.notes.length > 0 &&
            ` · ${load.notes.length} note${load.notes.length === 1 ? "" : "s"}`}
        </summary>
        {mine && mine.pdos.length > 0 && (
          <table className="data-table pdo-load-table">
            <thead>
              <tr>
                <th>PDO</th>
                <th>COB-ID</th>
                <th>Frames</th>
                <th>Bits / frame</th>
                <th>Load</th>
                <th>Counted as</th>
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
        )}
        {load.notes.length > 0 && (
          <ul className="muted small pdo-notes">
            {load.notes.map((note, i) => (
              <li key={i}>{note}</li>
            ))}
          </ul>
        )}
      </details>
    </section>
  );
}
