import { useMemo, useState, type ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { odAddress } from "../../lib/format";
import { fitProblem, pdoLabel, type FitRules, type ObjectInfo } from "./model";
import type { Pdo } from "./types";

const SHOWN = 40;

/** Matches "6041", "0x6064", "6064:00", "6064h" or words of the name. */
export function matchesObject(object: ObjectInfo, query: string): boolean {
  const q = query.trim().toLowerCase();
  if (!q) return true;
  const address = /^(?:0x)?([0-9a-f]{1,4})h?(?::(?:0x)?([0-9a-f]{1,2})h?)?$/.exec(q);
  if (address?.[1] !== undefined) {
    const index = Number.parseInt(address[1], 16);
    const sub = address[2] === undefined ? null : Number.parseInt(address[2], 16);
    if (object.index === index && (sub === null || object.subindex === sub)) return true;
  }
  const name = object.name.toLowerCase();
  return q.split(/\s+/).every((word) => name.includes(word));
}

/** Search the node's PDO-mappable objects and add one; what cannot fit is refused with why. */
export function ObjectPicker({
  pdo,
  objects,
  rules,
  onAdd,
}: {
  pdo: Pdo;
  objects: readonly ObjectInfo[];
  rules: FitRules;
  onAdd: (object: ObjectInfo) => void;
}): ReactNode {
  const { t } = useTranslation();
  const label = pdoLabel(pdo);
  const [query, setQuery] = useState("");
  const [refused, setRefused] = useState<string | null>(null);
  const found = useMemo(() => objects.filter((o) => matchesObject(o, query)), [objects, query]);

  function add(object: ObjectInfo): void {
    const problem = fitProblem(pdo, object, rules);
    setRefused(problem);
    if (problem === null) onAdd(object);
  }

  return (
    <div className="pdo-picker">
      <input
        type="search"
        className="wide"
        aria-label={t("pdo.picker.find", { label })}
        placeholder={t("pdo.picker.placeholder")}
        value={query}
        onChange={(e) => {
          setQuery(e.target.value);
          setRefused(null);
        }}
      />
      {refused && (
        <p className="error-text" role="alert">
          {refused}
        </p>
      )}
      {query.trim() !== "" && (
        <ul className="pdo-picker-list" aria-label={t("pdo.picker.objectsFor", { label })}>
          {found.slice(0, SHOWN).map((object) => {
            const problem = fitProblem(pdo, object, rules);
            const address = odAddress(object.index, object.subindex);
            return (
              <li key={address} className={problem ? "no-fit" : undefined} title={problem ?? ""}>
                <span className="mono small">{address}</span>
                <span className="pdo-picker-name">{object.name}</span>
                <span className="muted small">
                  {t("pdo.frame.bits", { bits: object.bits ?? "?" })} · {object.access}
                  {object.unit && ` · ${object.unit}`}
                </span>
                <button
                  type="button"
                  className="small"
                  aria-label={t("pdo.picker.add", { name: object.name, address })}
                  onClick={() => add(object)}
                >
                  {t("pdo.picker.addButton")}
                </button>
              </li>
            );
          })}
          {found.length === 0 && <li className="muted">{t("pdo.picker.noMatch")}</li>}
          {found.length > SHOWN && (
            <li className="muted small">{t("pdo.picker.more", { more: found.length - SHOWN })}</li>
          )}
        </ul>
      )}
    </div>
  );
}
