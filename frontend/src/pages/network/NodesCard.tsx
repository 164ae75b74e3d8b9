import { memo, type MouseEvent, type ReactNode } from "react";
import { Link, useNavigate } from "react-router";

import { api, call } from "../../api/client";
import { toApiError, type ApiError } from "../../api/errors";
import type { NmtCommandName, NodeInfo, ScanResult } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { NmtBadge, NmtDot } from "../../components/NmtDot";
import { QuickStopAllButton, QuickStopButton } from "../../components/QuickStopButton";
import { Spinner } from "../../components/Spinner";
import { formatAge, hex } from "../../lib/format";
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
  const fault = useLive((s) => s.faults[info.node]);
  if (!fault) return null;
  const register = fault.error_register;
  const bits = register === null || register === undefined ? "" : ` (1001h = ${hex(register, 2)})`;
  return (
    <Link
      to={nodeUrl(info.node, "faults")}
      className="error-lamp"
      aria-label={`Node ${info.node} in fault${bits}: open its faults`}
      title={`In fault${bits}`}
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
        <>
          Gone: the drive answers as <Link to={nodeUrl(info.moved_to)}>node {info.moved_to}</Link>{" "}
          now.{" "}
        </>
      ) : (
        "Gone: it does not answer. "
      )}
      <button
        type="button"
        className="small"
        {...configure.gate("forget a node", { disabled: forget.busy })}
        aria-label={`Forget node ${info.node}`}
        onClick={() => void forget.run()}
      >
        Forget
      </button>
      {forget.error && <ErrorText error={forget.error} />}
    </span>
  );
}

/** When no listed node sends a heartbeat, a lost node shows only when it is next asked. */
function NoHeartbeatHint({ infos }: { infos: readonly NodeInfo[] }): ReactNode {
  const live = useLive((s) => s.nodes);
  const online = infos.filter((i) => live[i.node]?.online ?? i.online);
  const beating = online.some(
    (i) => (live[i.node]?.heartbeat_age_ms ?? i.heartbeat_age_ms) != null,
  );
  if (online.length === 0 || beating) return null;
  return (
    <p className="muted small" role="note" aria-label="No heartbeats">
      No node sends a heartbeat (producer time 0), so ServoDesk notices a lost node only when it
      next asks it something. Set a heartbeat producer time (100 ms is usual) in the column above.
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
        <Link to={nodeUrl(info.node)} aria-label={`Open node ${info.node}`}>
          {info.node}
        </Link>{" "}
        <ErrorLamp info={info} />
      </td>
      <td>{info.name ?? "—"}</td>
      <td>{info.profile_label}</td>
      <td className="mono small">
        <span className="block" title="Vendor ID (1018h:01)">
          {hex(info.vendor_id)}
        </span>
        <span className="block" title="Product code (1018h:02)">
          {hex(info.product_code)}
        </span>
        <span className="block muted" title="Revision (1018h:03) and serial number (1018h:04)">
          rev {hex(info.revision)} · SN {hex(info.serial)}
        </span>
        {(info.software_version ?? info.hardware_version) && (
          <span
            className="block muted"
            title="Firmware (100Ah manufacturer software version) and hardware (1009h)"
          >
            FW {info.software_version ?? "—"}
            {info.hardware_version ? ` · HW ${info.hardware_version}` : ""}
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
          label={`NMT for node ${info.node}`}
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
  const configure = useMay("configure");
  const send = useAction((command: NmtCommandName) =>
    call(api.POST("/api/nmt", { body: { command } })),
  );
  return (
    <div className="broadcast" role="group" aria-label="Broadcast NMT">
      <span className="group-label">Broadcast NMT</span>
      {NMT_COMMANDS.map(({ command, label }) => (
        <button
          key={command}
          type="button"
          className="small"
          {...configure.gate("send NMT commands", { disabled: send.busy })}
          aria-label={`Broadcast ${label}`}
          onClick={() => void send.run(command)}
        >
          {label}
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
  const infos = useLive((s) => s.infos);
  const infosError = useLive((s) => s.infosError);
  return (
    <section className="card" aria-labelledby="nodes-heading">
      <header className="card-header">
        <h2 id="nodes-heading">Nodes</h2>
        <button
          type="button"
          className="primary"
          disabled={scan.busy}
          onClick={() => void scan.run()}
        >
          Scan
        </button>
        {scan.busy && <Spinner label="Scanning" />}
        {lastScan && !scan.busy && (
          <span className="muted" role="status">
            Found {lastScan.nodes.length} node{lastScan.nodes.length === 1 ? "" : "s"} in{" "}
            {lastScan.duration_ms} ms
          </span>
        )}
        <BroadcastNmt />
        <QuickStopAllButton />
      </header>
      <ErrorText error={scan.error ?? infosError} />
      {infos.length === 0 ? (
        <p className="muted">No nodes known yet. Connect the bus, then Scan.</p>
      ) : (
        // No scroll container here: it would clip the NMT menus; the table fits a laptop screen.
        <div>
          <table className="data-table nodes-table" aria-label="Nodes">
            <thead>
              <tr>
                <th scope="col">Node</th>
                <th scope="col">Name</th>
                <th scope="col">Profile</th>
                <th scope="col">Identity</th>
                <th scope="col">NMT state</th>
                <th scope="col">Heartbeat age</th>
                <th scope="col">Heartbeat producer</th>
                <th scope="col">Actions</th>
                <th scope="col" title="The node's latest commissioning record">
                  Record
                </th>
                <th scope="col">Motion</th>
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
