import { memo, type ReactNode } from "react";

import type { OdEntry, OdObject } from "../../api/types";
import { useTranslation } from "../../i18n";
import type { FilteredObject } from "../../lib/odFilter";
import { valueKey, type ValueMap } from "./values";

export interface Selection {
  index: number;
  subindex: number;
}

interface RowProps {
  item: FilteredObject;
  open: boolean;
  selected: Selection | null;
  values: ValueMap;
  onToggle: (index: number) => void;
  onSelect: (selection: Selection) => void;
}

function hex4(index: number): string {
  return index.toString(16).toUpperCase().padStart(4, "0");
}

function hex2(sub: number): string {
  return sub.toString(16).toUpperCase().padStart(2, "0");
}

/** A VAR (one entry at sub 0) is shown as a single row; arrays and records open up. */
export function isSingle(object: OdObject): boolean {
  return (
    object.subs.length === 1 &&
    object.subs[0]?.subindex === 0 &&
    object.object_type !== "array" &&
    object.object_type !== "record"
  );
}

function ValueCell({ values, entry }: { values: ValueMap; entry: OdEntry }): ReactNode {
  const shown = values[valueKey(entry.index, entry.subindex)];
  if (!shown) return <span className="od-value" />;
  return (
    <span className={`od-value mono${shown.failed ? " failed" : ""}`} title={shown.text}>
      {shown.text}
    </span>
  );
}

function ObjectRowView({ item, open, selected, values, onToggle, onSelect }: RowProps): ReactNode {
  const { t } = useTranslation();
  const { object } = item;
  const single = isSingle(object);
  const first = object.subs[0];
  const objectSelected = selected?.index === object.index && (single || !open);
  return (
    <li className="od-object">
      <div className={`od-row${objectSelected && single ? " selected" : ""}`}>
        {single ? (
          <span className="od-toggle-space" />
        ) : (
          <button
            type="button"
            className="od-toggle"
            aria-expanded={open}
            aria-label={t(open ? "od.tree.collapse" : "od.tree.expand", {
              index: hex4(object.index),
              name: object.name,
            })}
            onClick={() => onToggle(object.index)}
          >
            {open ? "▾" : "▸"}
          </button>
        )}
        <button
          type="button"
          className="od-select"
          aria-current={objectSelected && single ? "true" : undefined}
          onClick={() =>
            single && first
              ? onSelect({ index: object.index, subindex: 0 })
              : onToggle(object.index)
          }
        >
          <span className="od-index mono">{hex4(object.index)}</span>
          <span className="od-name">{object.name}</span>
        </button>
        {single && first ? (
          <ValueCell values={values} entry={first} />
        ) : (
          <span className="od-value muted small">
            {t("od.tree.entries", { entries: object.subs.length })}
          </span>
        )}
      </div>
      {!single && open && (
        <ul className="od-subs">
          {item.subs.map((entry) => {
            const isSelected =
              selected?.index === entry.index && selected.subindex === entry.subindex;
            return (
              <li key={entry.subindex} className={`od-row sub${isSelected ? " selected" : ""}`}>
                <span className="od-toggle-space" />
                <button
                  type="button"
                  className="od-select"
                  aria-current={isSelected ? "true" : undefined}
                  onClick={() => onSelect({ index: entry.index, subindex: entry.subindex })}
                >
                  <span className="od-index mono">:{hex2(entry.subindex)}</span>
                  <span className="od-name">{entry.name}</span>
                </button>
                <ValueCell values={values} entry={entry} />
              </li>
            );
          })}
        </ul>
      )}
    </li>
  );
}

// Re-render a row only when something it shows changed: during "Upload all" the value map
// changes four times a second, but each row looks only at its own entries.
const ObjectRow = memo(ObjectRowView, (a, b) => {
  if (
    a.item !== b.item ||
    a.open !== b.open ||
    a.onToggle !== b.onToggle ||
    a.onSelect !== b.onSelect
  ) {
    return false;
  }
  const index = a.item.object.index;
  const wasHere = a.selected?.index === index;
  const isHere = b.selected?.index === index;
  if (wasHere !== isHere || (isHere && a.selected?.subindex !== b.selected.subindex)) return false;
  if (a.values === b.values) return true;
  const shown = a.open || isSingle(a.item.object) ? a.item.subs : [];
  return shown.every(
    (e) => a.values[valueKey(e.index, e.subindex)] === b.values[valueKey(e.index, e.subindex)],
  );
});

interface TreeProps {
  items: readonly FilteredObject[];
  expanded: ReadonlySet<number>;
  selected: Selection | null;
  values: ValueMap;
  onToggle: (index: number) => void;
  onSelect: (selection: Selection) => void;
}

export function OdTreeView({
  items,
  expanded,
  selected,
  values,
  onToggle,
  onSelect,
}: TreeProps): ReactNode {
  const { t } = useTranslation();
  if (items.length === 0) return <p className="muted od-empty">{t("od.tree.noMatch")}</p>;
  return (
    <ul className="od-tree" aria-label={t("od.tree.label")}>
      {items.map((item) => (
        <ObjectRow
          key={item.object.index}
          item={item}
          // A search hit inside the subs opens the object; a click on its toggle still flips it.
          open={item.openForMatch !== expanded.has(item.object.index)}
          selected={selected}
          values={values}
          onToggle={onToggle}
          onSelect={onSelect}
        />
      ))}
    </ul>
  );
}
