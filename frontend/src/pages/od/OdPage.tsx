import { useCallback, useDeferredValue, useId, useMemo, useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import type { JobResult, OdEntry, SdoValue } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { countEntries, filterOd, parseOdQuery } from "../../lib/odFilter";
import { useApi } from "../../lib/useApi";
import { DictionarySource } from "./DictionarySource";
import { OdDetails } from "./OdDetails";
import { OdTreeView, type Selection } from "./OdTreeView";
import { UploadAll } from "./UploadAll";
import { fromRead, mergeResults, valueKey, type ValueMap } from "./values";

/** Browse the node's object dictionary, read and write any entry, upload all values. */
export function OdPage({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const searchId = useId();
  const tree = useApi(
    (signal) => call(api.GET("/api/nodes/{node}/od", { params: { path: { node } }, signal })),
    `od-${node}`,
  );
  const [query, setQuery] = useState("");
  // Typing stays responsive with 1000+ entries: the list filters at a lower priority.
  const deferredQuery = useDeferredValue(query);
  const [expanded, setExpanded] = useState<ReadonlySet<number>>(() => new Set());
  const [selected, setSelected] = useState<Selection | null>(null);
  const [values, setValues] = useState<ValueMap>({});

  const objects = tree.data?.objects;
  const items = useMemo(
    () => filterOd(objects ?? [], parseOdQuery(deferredQuery)),
    [objects, deferredQuery],
  );
  const total = useMemo(
    () => (objects ? objects.reduce((n, o) => n + o.subs.length, 0) : 0),
    [objects],
  );

  const entry: OdEntry | undefined = useMemo(() => {
    if (!selected || !objects) return undefined;
    return objects
      .find((o) => o.index === selected.index)
      ?.subs.find((s) => s.subindex === selected.subindex);
  }, [objects, selected]);

  const onToggle = useCallback((index: number) => {
    setExpanded((old) => {
      const next = new Set(old);
      if (!next.delete(index)) next.add(index);
      return next;
    });
  }, []);
  const onResults = useCallback(
    (results: readonly JobResult[]) => setValues((old) => mergeResults(old, results)),
    [],
  );
  const onValue = useCallback((value: SdoValue) => {
    setValues((old) => ({ ...old, [valueKey(value.index, value.subindex)]: fromRead(value) }));
  }, []);

  return (
    <div className="od-page">
      <div className="toolbar">
        <UploadAll node={node} onResults={onResults} />
        <DictionarySource node={node} tree={tree.data} onChanged={tree.reload} />
      </div>
      <ErrorText error={tree.error} />
      <div className="od-split">
        <section className="card od-browser" aria-label={t("od.page.objects")}>
          <div className="od-search">
            <label htmlFor={searchId} className="visually-hidden">
              {t("od.page.search")}
            </label>
            <input
              id={searchId}
              type="search"
              placeholder={t("od.page.searchPlaceholder")}
              value={query}
              onChange={(e) => setQuery(e.target.value)}
            />
            <span className="muted small" aria-live="polite">
              {tree.loading && !objects ? (
                <Spinner label={t("od.page.loading")} />
              ) : (
                t("od.page.count", { shown: countEntries(items), total })
              )}
            </span>
          </div>
          <div className={`od-scroll${query !== deferredQuery ? " stale" : ""}`}>
            {objects && (
              <OdTreeView
                items={items}
                expanded={expanded}
                selected={selected}
                values={values}
                onToggle={onToggle}
                onSelect={setSelected}
              />
            )}
          </div>
        </section>
        <div className="od-detail-pane">
          {entry ? (
            <OdDetails
              key={`${entry.index}:${entry.subindex}`}
              node={node}
              entry={entry}
              onValue={onValue}
            />
          ) : (
            <section className="card">
              <p className="muted">{t("od.page.selectHint")}</p>
            </section>
          )}
        </div>
      </div>
    </div>
  );
}
