import { useDeferredValue, useId, useMemo, useState, type ReactNode } from "react";

import type { NodeInfo } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { nodeTitle, odAddress } from "../../lib/format";
import { useApi } from "../../lib/useApi";
import {
  MAX_SIGNALS,
  QUICK_PICKS,
  addSignal,
  findEntries,
  findEntry,
  signalKey,
  type SignalChoice,
} from "./model";
import { nodeDictionary } from "./scopeApi";

/** Choose the signals: a node, then a quick pick or any object of its dictionary. */
export function SignalPicker({
  nodes,
  signals,
  onChange,
}: {
  nodes: readonly NodeInfo[];
  signals: readonly SignalChoice[];
  onChange: (signals: SignalChoice[]) => void;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const [picked, setPicked] = useState<number | null>(null);
  const node = picked ?? nodes[0]?.node ?? null;
  const dictionary = useApi(
    (signal) => (node === null ? Promise.resolve(null) : nodeDictionary(node, signal)),
    `scope-od-${node ?? "none"}`,
  );
  const objects = dictionary.data?.objects;
  const [query, setQuery] = useState("");
  const deferredQuery = useDeferredValue(query);
  const found = useMemo(
    () => (objects && deferredQuery.trim() ? findEntries(objects, deferredQuery) : null),
    [objects, deferredQuery],
  );
  const chosen = new Set(signals.map(signalKey));
  const full = signals.length >= MAX_SIGNALS;

  const add = (index: number, subindex: number, name: string): void => {
    if (node !== null) onChange(addSignal(signals, { node, index, subindex, name }));
  };
  const remove = (key: string): void => onChange(signals.filter((s) => signalKey(s) !== key));

  return (
    <section className="card scope-signals" aria-labelledby={`${id}-h`}>
      <header className="card-header">
        <h2 id={`${id}-h`}>{t("scope.signals.heading")}</h2>
        <span className="muted small">
          {t("scope.signals.count", { count: signals.length, max: MAX_SIGNALS })}
        </span>
      </header>
      {nodes.length === 0 ? (
        <p className="muted">{t("scope.signals.noNodes")}</p>
      ) : (
        <>
          <div className="inline">
            <label htmlFor={`${id}-node`}>{t("scope.signals.node")}</label>
            <select
              id={`${id}-node`}
              value={node ?? ""}
              onChange={(e) => setPicked(Number(e.target.value))}
            >
              {nodes.map((info) => (
                <option key={info.node} value={info.node}>
                  {nodeTitle(info.node, info)}
                </option>
              ))}
            </select>
            {dictionary.loading && <Spinner label={t("scope.signals.loadingDictionary")} />}
          </div>
          <ErrorText error={dictionary.error} onRetry={dictionary.reload} />
          <div className="scope-quick" role="group" aria-label={t("scope.signals.quickPicks")}>
            {QUICK_PICKS.map((pick) => {
              const entry = findEntry(objects, pick.index);
              const key = node === null ? "" : signalKey({ node, index: pick.index, subindex: 0 });
              const on = chosen.has(key);
              const missing = objects !== undefined && entry === undefined;
              return (
                <button
                  key={pick.index}
                  type="button"
                  className={`small scope-pick${on ? " on" : ""}`}
                  aria-pressed={on}
                  disabled={missing || (full && !on)}
                  title={
                    missing
                      ? t("scope.signals.missing", {
                          node: node ?? "",
                          address: odAddress(pick.index),
                        })
                      : `${entry?.name ?? pick.name} (${odAddress(pick.index)})`
                  }
                  onClick={() => (on ? remove(key) : add(pick.index, 0, entry?.name ?? pick.name))}
                >
                  {t(pick.label)} <span className="mono">{odAddress(pick.index)}</span>
                </button>
              );
            })}
          </div>
          <label htmlFor={`${id}-find`} className="visually-hidden">
            {t("scope.signals.findLabel", { node })}
          </label>
          <input
            id={`${id}-find`}
            type="search"
            className="wide"
            placeholder={t("scope.signals.findPlaceholder")}
            value={query}
            onChange={(e) => setQuery(e.target.value)}
          />
          {found && (
            <ul className="scope-found" aria-label={t("scope.signals.found", { node: node ?? "" })}>
              {found.entries.map((entry) => {
                const address = odAddress(entry.index, entry.subindex);
                const key =
                  node === null
                    ? ""
                    : signalKey({ node, index: entry.index, subindex: entry.subindex });
                return (
                  <li key={address}>
                    <span className="mono small">{address}</span>
                    <span className="scope-found-name">{entry.name}</span>
                    <span className="muted small">
                      {entry.unit}
                      {!entry.pdoMappable && t("scope.signals.sdoOnly")}
                    </span>
                    <button
                      type="button"
                      className="small"
                      aria-label={t("scope.signals.addLabel", { name: entry.name, address })}
                      disabled={full || chosen.has(key)}
                      onClick={() => add(entry.index, entry.subindex, entry.name)}
                    >
                      {chosen.has(key) ? t("scope.signals.added") : t("scope.signals.add")}
                    </button>
                  </li>
                );
              })}
              {found.total === 0 && <li className="muted">{t("scope.signals.noMatch")}</li>}
              {found.total > found.entries.length && (
                <li className="muted small">
                  {t("scope.signals.more", { count: found.total - found.entries.length })}
                </li>
              )}
            </ul>
          )}
        </>
      )}
      {signals.length > 0 && (
        <ul className="scope-chosen" aria-label={t("scope.signals.chosen")}>
          {signals.map((signal) => {
            const key = signalKey(signal);
            const address = odAddress(signal.index, signal.subindex);
            return (
              <li key={key}>
                <span className="badge">{t("scope.signals.nodeBadge", { node: signal.node })}</span>
                <span className="mono small">{address}</span>
                <span className="scope-found-name">{signal.name}</span>
                <button
                  type="button"
                  className="icon-button"
                  aria-label={t("scope.signals.removeLabel", {
                    node: signal.node,
                    name: signal.name,
                    address,
                  })}
                  title={t("scope.signals.remove")}
                  onClick={() => remove(key)}
                >
                  ×
                </button>
              </li>
            );
          })}
        </ul>
      )}
      {full && <p className="muted small">{t("scope.signals.full", { max: MAX_SIGNALS })}</p>}
    </section>
  );
}
