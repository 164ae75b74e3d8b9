import { memo, type MouseEvent, type ReactNode } from "react";
import { Link, useNavigate } from "react-router";

import { api, call } from "../../api/client";
import { toApiError, type ApiError } from "../../api/errors";
import type { NmtCommandName, NodeInfo, ScanResult } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { NmtBadge, NmtDot } from "../../components/NmtDot";
import { QuickStopAllButton, QuickStopButton } from "../../components/QuickStopButton";
import { Spinner } from "../../components/Spinner";
import { Trans, useTranslation } from "../../i18n";
import { formatAge, hex, profileLabel } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useLive, useLiveStore } from "../../live/context";
import { refreshNodes } from "../../live/nodes";
import { nodeUrl } from "../../nav/paths";
import { useMay } from "../../session/context";
import { CommissionChip } from "./CommissionChip";
import { HeartbeatEditor } from "./HeartbeatEditor";
import type { LatestRecord } from "./latestRecords";
import { NMT_COMMANDS, NmtMenu } from "./NmtMenu";

// Live cells subscribe to their own node, so the table itself does not re-render at 5 Hz.
function LiveState({ info }: { info: NodeInfo }): ReactNode {
  const live = useLive((s) => s.nodes[info.node]);
  return (
    <NmtBadge state={live?.nmt_state ?? info.nmt_state} online={live?.online ?? info.online} />
  );
}

function LiveDot({ info }: { info: NodeInfo }): ReactNode {
  const live = useLive((s) => s.nodes[info.node]);
  return <NmtDot state={live?.nmt_state ?? info.nmt_state} online={live?.online ?? info.online} />;
}

/** The error register (1001h) of the node's active EMCY: lit while it is in fault. */
function ErrorLamp({ info }: { info: NodeInfo }): ReactNode {
  const { t } = useTranslation();
  const fault = useLive((s) => s.faults[info.node]);
  if (!fault) return null;
  const register = fault.error_register;
  const known = register !== null && register !== undefined;
  const values = { node: info.node, register: known ? hex(register, 2) : "" };
  return (
    <Link
      to={nodeUrl(info.node, "faults")}
      className="error-lamp"
      aria-label={t(known ? "network.nodes.faultLampRegister" : "network.nodes.faultLamp", values)}
      title={t(
        known ? "network.nodes.faultLampTitleRegister" : "network.nodes.faultLampTitle",
        values,
      )}
    >
      ⚠
    </Link>
  );
}

function LiveAge({ info }: { info: NodeInfo }): ReactNode {
  const age = useLive((s) => s.nodes[info.node]?.heartbeat_age_ms);
  return <>{formatAge(age === undefined ? info.heartbeat_age_ms : age)}</>;
}

/** A node that does not answer: where its drive answers now, if known, and Forget. */
function GoneNote({ info }: { info: NodeInfo }): ReactNode {
  const { t } = useTranslation();
  const online = useLive((s) => s.nodes[info.node]?.online ?? info.online);
  const store = useLiveStore();
  const configure = useMay("configure");
  const forget = useAction(async () => {
    const answer = await api.DELETE("/api/nodes/{node}", { params: { path: { node: info.node } } });
    if (!answer.response.ok) {
      throw toApiError(answer.response.status, answer.error, answer.response.statusText);
    }
    await refreshNodes(store);
  });
  if (online) return null;
  return (
    <span className="block small gone-note">
      {info.moved_to ? (
        <Trans
          i18nKey="network.nodes.goneMoved"
          values={{ node: info.moved_to }}
          components={{ node: <Link to={nodeUrl(info.moved_to)} /> }}
        />
      ) : (
        t("network.nodes.gone")
      )}
      <button
        type="button"
        className="small"
        {...configure.gate(t("network.gate.forget"), { disabled: forget.busy })}
        aria-label={t("network.nodes.forgetLabel", { node: info.node })}
        onClick={() => void forget.run()}
      >
        {t("network.nodes.forget")}
      </button>
      {forget.error && <ErrorText error={forget.error} />}
    </span>
  );
}

/** When no listed node sends a heartbeat, a lost node shows only when it is next asked. */
function NoHeartbeatHint({ infos }: { infos: readonly NodeInfo[] }): ReactNode {
  const { t } = useTranslation();
  const live = useLive((s) => s.nodes);
  const online = infos.filter((i) => live[i.node]?.online ?? i.online);
  const beating = online.some(
    (i) => (live[i.node]?.heartbeat_age_ms ?? i.heartbeat_age_ms) != null,
  );
  if (online.length === 0 || beating) return null;
  return (
    <p className="muted small" role="note" aria-label={t("network.nodes.noHeartbeats")}>
      {t("network.nodes.noHeartbeatsText")}
    </p>
  );
}

const INTERACTIVE = "a, button, input, select, textarea, summary, details, label, form";

const NodeRow = memo(function NodeRow({
  info,
  commission,
}: {
  info: NodeInfo;
  /** The node's latest commissioning record; null: none; undefined: not loaded. */
  commission: LatestRecord | null | undefined;
}): ReactNode {
  const { t } = useTranslation(); // memo: the language is not a prop, so subscribe here
  const navigate = useNavigate();
  const store = useLiveStore();
  const nmt = useAction(async (command: NmtCommandName) => {
    const updated = await call(
      api.POST("/api/nodes/{node}/nmt", {
        params: { path: { node: info.node } },
        body: { command },
      }),
    );
    store.upsertInfo(updated);
  });

  function open(event: MouseEvent<HTMLTableRowElement>): void {
    // Clicks on the row's own controls do their job, not navigation.
    if (event.target instanceof Element && event.target.closest(INTERACTIVE)) return;
    void navigate(nodeUrl(info.node));
  }

  return (
    <tr className="clickable" onClick={open}>
      <td>
        <LiveDot info={info} />{" "}
        <Link to={nodeUrl(info.node)} aria-label={t("network.nodes.open", { node: info.node })}>
          {info.node}
        </Link>{" "}
        <ErrorLamp info={info} />
      </td>
      <td>{info.name ?? "—"}</td>
      <td>{profileLabel(info)}</td>
      <td className="mono small">
        <span className="block" title={t("network.nodes.vendorId")}>
          {hex(info.vendor_id)}
        </span>
        <span className="block" title={t("network.nodes.productCode")}>
          {hex(info.product_code)}
        </span>
        <span className="block muted" title={t("network.nodes.revisionSerialTitle")}>
          {t("network.nodes.revisionSerial", {
            revision: hex(info.revision),
            serial: hex(info.serial),
          })}
        </span>
        {(info.software_version ?? info.hardware_version) && (
          <span className="block muted" title={t("network.nodes.versionsTitle")}>
            {t("network.nodes.firmware", { version: info.software_version ?? "—" })}
            {info.hardware_version
              ? t("network.nodes.hardware", { version: info.hardware_version })
              : ""}
          </span>
        )}
      </td>
      <td>
        <LiveState info={info} />
        <GoneNote info={info} />
      </td>
      <td className="num">
        <LiveAge info={info} />
      </td>
      <td>
        <HeartbeatEditor node={info.node} />
      </td>
      <td>
        <NmtMenu
          label={t("network.nodes.nmtFor", { node: info.node })}
          disabled={nmt.busy}
          onCommand={(c) => void nmt.run(c)}
        />
        {nmt.error && <ErrorText error={nmt.error} />}
      </td>
      <td>
        <CommissionChip node={info.node} latest={commission} />
      </td>
      <td>
        <QuickStopButton node={info.node} compact />
      </td>
    </tr>
  );
});

function BroadcastNmt(): ReactNode {
  const { t } = useTranslation();
  const configure = useMay("configure");
  const send = useAction((command: NmtCommandName) =>
    call(api.POST("/api/nmt", { body: { command } })),
  );
  return (
    <div className="broadcast" role="group" aria-label={t("network.nodes.broadcast")}>
      <span className="group-label">{t("network.nodes.broadcast")}</span>
      {NMT_COMMANDS.map(({ command, labelKey }) => (
        <button
          key={command}
          type="button"
          className="small"
          {...configure.gate(t("network.gate.nmt"), { disabled: send.busy })}
          aria-label={t("network.nodes.broadcastCommand", { command: t(labelKey) })}
          onClick={() => void send.run(command)}
        >
          {t(labelKey)}
        </button>
      ))}
      <ErrorText error={send.error} />
    </div>
  );
}

interface ScanProps {
  scan: { run: () => Promise<ScanResult | undefined>; busy: boolean; error: ApiError | null };
  lastScan: ScanResult | null;
  /** Each node's latest commissioning record; null while it loads (or could not load). */
  commissioning?: ReadonlyMap<number, LatestRecord> | null;
}

/** Nodes on the bus: identity, live NMT state and heartbeat, NMT commands, scan. */
export function NodesCard({ scan, lastScan, commissioning = null }: ScanProps): ReactNode {
  const { t } = useTranslation();
  const infos = useLive((s) => s.infos);
  const infosError = useLive((s) => s.infosError);
  return (
    <section className="card" aria-labelledby="nodes-heading">
      <header className="card-header">
        <h2 id="nodes-heading">{t("network.nodes.heading")}</h2>
        <button
          type="button"
          className="primary"
          disabled={scan.busy}
          onClick={() => void scan.run()}
        >
          {t("network.nodes.scan")}
        </button>
        {scan.busy && <Spinner label={t("network.nodes.scanning")} />}
        {lastScan && !scan.busy && (
          <span className="muted" role="status">
            {t("network.nodes.found", {
              count: lastScan.nodes.length,
              ms: lastScan.duration_ms,
            })}
          </span>
        )}
        <BroadcastNmt />
        <QuickStopAllButton />
      </header>
      <ErrorText error={scan.error ?? infosError} />
      {infos.length === 0 ? (
        <p className="muted">{t("network.nodes.empty")}</p>
      ) : (
        // No scroll container here: it would clip the NMT menus; the table fits a laptop screen.
        <div>
          <table className="data-table nodes-table" aria-label={t("network.nodes.tableLabel")}>
            <thead>
              <tr>
                <th scope="col">{t("network.nodes.colNode")}</th>
                <th scope="col">{t("network.nodes.colName")}</th>
                <th scope="col">{t("network.nodes.colProfile")}</th>
                <th scope="col">{t("network.nodes.colIdentity")}</th>
                <th scope="col">{t("network.nodes.colNmt")}</th>
                <th scope="col">{t("network.nodes.colHeartbeatAge")}</th>
                <th scope="col">{t("network.nodes.colHeartbeatProducer")}</th>
                <th scope="col">{t("network.nodes.colActions")}</th>
                <th scope="col" title={t("network.nodes.colRecordTitle")}>
                  {t("network.nodes.colRecord")}
                </th>
                <th scope="col">{t("network.nodes.colMotion")}</th>
              </tr>
            </thead>
            <tbody>
              {infos.map((info) => (
                <NodeRow
                  key={info.node}
                  info={info}
                  commission={commissioning ? (commissioning.get(info.node) ?? null) : undefined}
                />
              ))}
            </tbody>
          </table>
          <NoHeartbeatHint infos={infos} />
        </div>
      )}
    </section>
  );
}
