import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { odAddress } from "../../lib/format";
import { moveEntry, pdoLabel, type FitRules, type Lookup, type ObjectInfo } from "./model";
import { ObjectPicker } from "./ObjectPicker";
import type { Pdo } from "./types";

/** A draft PDO's mapped objects in order, with remove / move, and the picker to add one. */
export function MappingEditor({
  pdo,
  lookup,
  objects,
  rules,
  onChange,
}: {
  pdo: Pdo;
  lookup: Lookup;
  objects: readonly ObjectInfo[];
  rules: FitRules;
  onChange: (pdo: Pdo) => void;
}): ReactNode {
  const { t } = useTranslation();
  const label = pdoLabel(pdo);
  const setMapping = (mapping: Pdo["mapping"]): void => onChange({ ...pdo, mapping });
  return (
    <div className="pdo-mapping-editor">
      <ol className="pdo-entries" aria-label={t("pdo.mapping.entries", { label })}>
        {pdo.mapping.map((entry, i) => {
          const address = odAddress(entry.index, entry.subindex);
          const name = lookup(entry.index, entry.subindex)?.name ?? entry.name ?? address;
          return (
            <li key={`${address}-${i}`}>
              <span className="pdo-entry-name">{name}</span>
              <span className="mono small muted">
                {address} · {t("pdo.frame.bits", { bits: entry.bits })}
              </span>
              <span className="spacer" />
              <button
                type="button"
                className="small"
                aria-label={t("pdo.mapping.moveEarlier", { name })}
                disabled={i === 0}
                onClick={() => setMapping(moveEntry(pdo.mapping, i, i - 1))}
              >
                ↑
              </button>
              <button
                type="button"
                className="small"
                aria-label={t("pdo.mapping.moveLater", { name })}
                disabled={i === pdo.mapping.length - 1}
                onClick={() => setMapping(moveEntry(pdo.mapping, i, i + 1))}
              >
                ↓
              </button>
              <button
                type="button"
                className="small"
                aria-label={t("pdo.mapping.removeFrom", { name, label })}
                onClick={() => setMapping(pdo.mapping.filter((_, j) => j !== i))}
              >
                {t("pdo.mapping.remove")}
              </button>
            </li>
          );
        })}
      </ol>
      <ObjectPicker
        pdo={pdo}
        objects={objects}
        rules={rules}
        onAdd={(object) =>
          setMapping([
            ...pdo.mapping,
            {
              index: object.index,
              subindex: object.subindex,
              bits: object.bits ?? 0,
              name: object.name,
            },
          ])
        }
      />
    </div>
  );
}
