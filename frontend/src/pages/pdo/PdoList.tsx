import { useState, type ReactNode } from "react";

import { useTranslation } from "../../i18n";
import type { MessageKey } from "../../i18n";
import { PdoCard } from "./PdoCard";
import { pdoChanges, pdoKey, pdoLabel, type FitRules, type Lookup, type ObjectInfo } from "./model";
import type { Pdo, PdoKind, Problem } from "./types";

interface Props {
  /** The draft's PDOs, or the device's when there is no draft. */
  shown: readonly Pdo[];
  device: readonly Pdo[];
  draft: boolean;
  /** Changes when a new draft replaces the old one (resets the editors' text fields). */
  version: number;
  problems: readonly Problem[];
  lookup: Lookup;
  objects: readonly ObjectInfo[];
  rules: FitRules;
  onChange: (pdo: Pdo) => void;
}

const GROUPS: { kind: PdoKind; title: MessageKey; hint: MessageKey }[] = [
  { kind: "rpdo", title: "pdo.list.rpdoTitle", hint: "pdo.list.rpdoHint" },
  { kind: "tpdo", title: "pdo.list.tpdoTitle", hint: "pdo.list.tpdoHint" },
];

function unused(pdo: Pdo): boolean {
  return !pdo.valid && pdo.mapping.length === 0;
}

/** The node's RPDOs and TPDOs as cards; PDOs neither valid nor mapped fold into one line. */
export function PdoList({
  shown,
  device,
  draft,
  version,
  problems,
  lookup,
  objects,
  rules,
  onChange,
}: Props): ReactNode {
  const { t } = useTranslation();
  const [showUnused, setShowUnused] = useState(false);
  const deviceByKey = new Map(device.map((p) => [pdoKey(p), p]));
  return (
    <>
      {GROUPS.map((group) => {
        const pdos = shown.filter((p) => p.kind === group.kind);
        // A PDO a problem names, or that the draft changes, stays in view.
        const hidden = showUnused
          ? []
          : pdos.filter(
              (p) =>
                unused(p) &&
                !problems.some((x) => x.kind === p.kind && x.number === p.number) &&
                !(draft && pdoChanges(deviceByKey.get(pdoKey(p)), p).length > 0),
            );
        return (
          <section key={group.kind} className="pdo-group" aria-label={t(group.title)}>
            <header className="pdo-group-header">
              <h2>{t(group.title)}</h2>
              <span className="muted small">{t(group.hint)}</span>
            </header>
            {pdos
              .filter((p) => !hidden.includes(p))
              .map((pdo) => (
                <PdoCard
                  key={`${pdoKey(pdo)}-${version}`}
                  pdo={pdo}
                  device={deviceByKey.get(pdoKey(pdo))}
                  draft={draft}
                  problems={problems.filter((x) => x.kind === pdo.kind && x.number === pdo.number)}
                  lookup={lookup}
                  objects={objects}
                  rules={rules}
                  onChange={onChange}
                />
              ))}
            {hidden.length > 0 && (
              <p className="muted small pdo-unused">
                {t("pdo.list.unused", {
                  pdos: hidden.map(pdoLabel).join(t("common.listSeparator")),
                })}{" "}
                <button type="button" className="link-button" onClick={() => setShowUnused(true)}>
                  {t("pdo.list.showThem")}
                </button>
              </p>
            )}
          </section>
        );
      })}
    </>
  );
}
