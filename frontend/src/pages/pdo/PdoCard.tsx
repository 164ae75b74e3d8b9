import { memo, useMemo, type ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { odAddress } from "../../lib/format";
import { ByteLayout } from "./ByteLayout";
import { CommEditor, CommFacts } from "./CommFields";
import { MappingEditor } from "./MappingEditor";
import {
  frameLayout,
  MAX_BITS,
  pdoChanges,
  pdoLabel,
  pdoObjects,
  placeProblems,
  problemText,
  sameMapping,
  type FitRules,
  type Lookup,
  type ObjectInfo,
} from "./model";
import type { Pdo, Problem } from "./types";

interface Props {
  /** What is shown: the device's PDO, or the draft's when there is a draft. */
  pdo: Pdo;
  /** The device's PDO when `pdo` is a draft (undefined: no draft, or new). */
  device?: Pdo | undefined;
  draft: boolean;
  problems: readonly Problem[];
  lookup: Lookup;
  objects: readonly ObjectInfo[];
  rules: FitRules;
  onChange: (pdo: Pdo) => void;
}

/** One RPDO or TPDO: communication parameter, the frame's byte layout, and in a draft the
 * editor, what changes against the device and the server's problems with it. */
export const PdoCard = memo(function PdoCard({
  pdo,
  device,
  draft,
  problems,
  lookup,
  objects,
  rules,
  onChange,
}: Props): ReactNode {
  const { t } = useTranslation();
  const label = pdoLabel(pdo);
  const layout = useMemo(() => frameLayout(pdo.mapping, lookup), [pdo.mapping, lookup]);
  const changes = draft ? pdoChanges(device, pdo) : [];
  const mappingChanged = draft && device !== undefined && !sameMapping(device.mapping, pdo.mapping);
  const placed = useMemo(() => placeProblems(pdo, problems), [pdo, problems]);
  // Objects inside the frame carry their problems; those past 64 bits and the rest are
  // listed under the PDO (with the comm fields' when not editing: no field to show them at).
  const inFrame = new Map(
    [...placed.atEntry].filter(([position]) => {
      const block = layout.blocks[position];
      return block !== undefined && block.startBit < MAX_BITS;
    }),
  );
  const listed = problems.filter(
    (p) =>
      ![...inFrame.values()].some((list) => list.includes(p)) &&
      !(draft && [...placed.atField.values()].some((list) => list.includes(p))),
  );
  const frameNotes = new Map([...inFrame].map(([k, list]) => [k, list.map(problemText)]));
  const classes = ["card", "pdo-card", pdo.valid ? "" : "invalid", changes.length ? "changed" : ""];

  return (
    <section
      className={classes.filter(Boolean).join(" ")}
      aria-label={draft ? t("pdo.card.draftLabel", { label }) : label}
      data-testid={`pdo-${pdo.kind}${pdo.number}`}
    >
      <header className="card-header">
        <h3>{label}</h3>
        <span className={`badge ${pdo.valid ? "pdo-valid" : "pdo-off"}`}>
          {pdo.valid ? t("pdo.card.valid") : t("pdo.card.notValid")}
        </span>
        {changes.length > 0 && (
          <span className="badge pdo-draft">{t("pdo.card.draftChanged")}</span>
        )}
        <span className="muted small">{pdoObjects(pdo)}</span>
      </header>
      {draft ? (
        <CommEditor pdo={pdo} rules={rules} problems={placed.atField} onChange={onChange} />
      ) : (
        <CommFacts pdo={pdo} />
      )}
      <ByteLayout layout={layout} label={t("pdo.card.frame", { label })} problems={frameNotes} />
      {mappingChanged && (
        <div className="pdo-device-now">
          <span className="muted small">{t("pdo.card.onDevice")}</span>
          <ByteLayout
            layout={frameLayout(device.mapping, lookup)}
            label={t("pdo.card.frameOnDevice", { label })}
          />
        </div>
      )}
      {changes.length > 0 && (
        <p className="small pdo-changes">
          <strong>{t("pdo.card.changes")}</strong> {changes.join(t("pdo.card.changeSeparator"))}
        </p>
      )}
      {listed.length > 0 && (
        <ul className="pdo-problems" aria-label={t("pdo.card.problems", { label })}>
          {listed.map((p, i) => (
            <li key={i} className="error-text">
              {p.index != null && (
                <span className="mono">{odAddress(p.index, p.subindex ?? 0)}: </span>
              )}
              {problemText(p)}
            </li>
          ))}
        </ul>
      )}
      {draft && (
        <MappingEditor
          pdo={pdo}
          lookup={lookup}
          objects={objects}
          rules={rules}
          onChange={onChange}
        />
      )}
    </section>
  );
});
