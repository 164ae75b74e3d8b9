import { useCallback, useMemo, useRef, useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import type { OdObject } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useLive } from "../../live/context";
import { useAction, useApi } from "../../lib/useApi";
import { ApplyResult } from "./ApplyResult";
import { BusLoadView } from "./BusLoadView";
import { DraftBar } from "./DraftBar";
import { ExportButtons } from "./ExportButtons";
import { LiveCheck } from "./LiveCheck";
import { fitRules, mergePdos, pdoKey, sortPdos, typeBits, type ObjectInfo } from "./model";
import { ModeWizard } from "./ModeWizard";
import {
  busLoad,
  listPdos,
  pdoRules,
  validatePdos,
  type ApplyOutcome,
  type SyncSource,
} from "./pdoApi";
import { PdoList } from "./PdoList";
import type { LoadSettings, Pdo, Problem, Validation } from "./types";

const DEFAULT_SETTINGS: LoadSettings = { threshold: 70, masterPeriodMs: 10 };

interface Draft {
  pdos: Pdo[];
  source: string;
  /** Changed by hand since it was made ("… (edited)"). */
  edited: boolean;
  version: number;
}

/** Every sub-entry of the dictionary as the mapping editor needs it. */
function objectInfos(objects: readonly OdObject[]): ObjectInfo[] {
  return objects.flatMap((o) =>
    o.subs.map((s) => ({
      index: s.index,
      subindex: s.subindex,
      name: s.name,
      unit: s.unit,
      access: s.access,
      dataTypeName: s.data_type_name,
      bits: typeBits(s.data_type_name),
      mappable: s.pdo_mappable,
    })),
  );
}

/** The node's PDOs as the device has them; a draft by purpose or by hand; validate, apply,
 * and check the result live. */
export function PdoPage({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const pdos = useApi((signal) => listPdos(node, signal), `pdos-${node}`);
  const od = useApi(
    (signal) => call(api.GET("/api/nodes/{node}/od", { params: { path: { node } }, signal })),
    `od-${node}`,
  );
  const rulesApi = useApi((signal) => pdoRules(node, signal), `pdo-rules-${node}`);
  const nmtState = useLive((s) => s.infos.find((i) => i.node === node)?.nmt_state);
  const [settings, setSettings] = useState<LoadSettings>(DEFAULT_SETTINGS);
  // One resource whatever the settings: the bars stay while a changed setting reloads them.
  const current = useApi((signal) => busLoad(settings, signal), "bus-load");
  const [draft, setDraft] = useState<Draft | null>(null);
  const [validation, setValidation] = useState<Validation | null>(null);
  const [problems, setProblems] = useState<Problem[]>([]);
  const [outcome, setOutcome] = useState<ApplyOutcome | null>(null);
  // the user says SYNC comes from the machine's controller: synchronous PDOs can be written
  // while ServoDesk produces none and none is heard
  const [syncExternal, setSyncExternal] = useState(false);
  const syncSource = syncExternal ? "external" : null;

  // The last validation request wins (settings typed fast re-validate in quick succession).
  const validationSeq = useRef(0);
  const validate = useAction(async (pdos: Pdo[], with_: LoadSettings, source: SyncSource) => {
    const seq = ++validationSeq.current;
    const result = await validatePdos(node, pdos, with_, source);
    if (seq !== validationSeq.current) return;
    setValidation(result);
    setProblems(result.problems);
  });
  const forgetValidation = useCallback(() => {
    validationSeq.current += 1;
    setValidation(null);
    setProblems([]);
  }, []);
  const changeSettings = (next: LoadSettings): void => {
    setSettings(next);
    current.reload();
    // a checked draft is checked again: the server compares against the settings
    if (draft && (validation || validate.busy)) void validate.run(draft.pdos, next, syncSource);
  };
  const changeSyncExternal = (external: boolean): void => {
    setSyncExternal(external);
    // a checked draft is checked again: the answer depends on where SYNC comes from
    if (draft && (validation || validate.busy)) {
      void validate.run(draft.pdos, settings, external ? "external" : null);
    }
  };

  const infos = useMemo(() => objectInfos(od.data?.objects ?? []), [od.data]);
  const byAddress = useMemo(
    () => new Map(infos.map((o) => [`${o.index}:${o.subindex}`, o])),
    [infos],
  );
  const lookup = useCallback(
    (index: number, subindex: number) => byAddress.get(`${index}:${subindex}`),
    [byAddress],
  );
  const mappable = useMemo(() => infos.filter((o) => o.mappable), [infos]);
  const rules = useMemo(() => fitRules(rulesApi.data), [rulesApi.data]);
  const device = useMemo(() => sortPdos(pdos.data ?? []), [pdos.data]);

  const startDraft = useCallback(
    (next: Pdo[], source: string) => {
      setDraft((old) => ({
        pdos: sortPdos(mergePdos(device, next)),
        source,
        edited: false,
        version: (old?.version ?? 0) + 1,
      }));
      forgetValidation();
      setOutcome(null);
    },
    [device, forgetValidation],
  );
  const onChange = useCallback(
    (pdo: Pdo) => {
      setDraft(
        (old) =>
          old && {
            ...old,
            pdos: old.pdos.map((p) => (pdoKey(p) === pdoKey(pdo) ? pdo : p)),
            edited: true,
          },
      );
      forgetValidation();
    },
    [forgetValidation],
  );
  const onOutcome = useCallback(
    (result: ApplyOutcome) => {
      setOutcome(result);
      if (result.result === "applied") {
        pdos.setData(() => result.pdos);
        setDraft(null);
        forgetValidation();
        current.reload();
      } else if (result.result === "rejected") {
        setProblems(result.problems);
      } else {
        pdos.reload();
      }
    },
    [pdos, current, forgetValidation],
  );

  const load = validation?.bus_load ?? current.data;
  return (
    <div className="pdo-page">
      <div className="toolbar">
        <button type="button" disabled={pdos.loading} onClick={pdos.reload}>
          {t("pdo.page.readAgain")}
        </button>
        {pdos.loading && <Spinner label={t("pdo.page.reading")} />}
        <span className="spacer" />
        <span className="inline">
          <ExportButtons node={node} />
        </span>
      </div>
      <ErrorText error={pdos.error} onRetry={pdos.reload} />
      <ErrorText error={od.error} />
      <ErrorText error={rulesApi.error} onRetry={rulesApi.reload} />
      {outcome && <ApplyResult outcome={outcome} onClose={() => setOutcome(null)} />}
      <ModeWizard
        node={node}
        disabled={!pdos.data}
        onDraft={startDraft}
        onEditCurrent={() => startDraft(device, t("pdo.page.fromDevice"))}
      />
      {draft && (
        <DraftBar
          node={node}
          device={device}
          draft={draft.pdos}
          source={draft.edited ? t("pdo.page.edited", { source: draft.source }) : draft.source}
          rules={rulesApi.data}
          nmtState={nmtState}
          validation={validation}
          validating={validate.busy}
          validateError={validate.error}
          syncExternal={syncExternal}
          onSyncExternal={changeSyncExternal}
          onValidate={() => void validate.run(draft.pdos, settings, syncSource)}
          onOutcome={onOutcome}
          onDiscard={() => {
            setDraft(null);
            forgetValidation();
          }}
        />
      )}
      {load && (
        <BusLoadView
          load={load}
          node={node}
          title={validation ? t("pdo.page.busLoadDraft") : t("pdo.page.busLoadNow")}
          open={validation !== null}
          settings={settings}
          onSettings={changeSettings}
        />
      )}
      <ErrorText error={validation ? null : current.error} />
      {pdos.data && (
        <PdoList
          shown={draft?.pdos ?? device}
          device={device}
          draft={draft !== null}
          version={draft?.version ?? 0}
          problems={problems}
          lookup={lookup}
          objects={mappable}
          rules={rules}
          onChange={onChange}
        />
      )}
      {pdos.data && !draft && <LiveCheck node={node} device={device} />}
    </div>
  );
}
