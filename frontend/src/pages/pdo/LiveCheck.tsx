import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { odAddress } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { formatCobId, formatRate, isSynchronous, pdoLabel } from "./model";
import { SyncControl } from "./SyncControl";
import type { LivePdo, LiveValue, Pdo } from "./types";
import { useLiveCapture } from "./useLiveCapture";

/** One decoded value as the server shows it (bit fields in hex, scaled units converted), its
 * meaning in words when it has one ("0x0250 · Switch on disabled"), the frame's bytes and the
 * raw number in the tooltip. */
function Value({ value: v }: { value: LiveValue }): ReactNode {
  const { t } = useTranslation();
  const address = odAddress(v.index, v.subindex);
  const raw = v.value == null ? "" : ` = ${String(v.value)}${v.unit ? ` (${v.unit})` : ""}`;
  let shown: string;
  if (v.display) shown = v.display;
  else if (v.value == null) shown = v.raw || "—";
  else shown = `${String(v.value)}${v.unit ? ` ${v.unit}` : ""}`;
  return (
    <div>
      <dt title={address}>{v.name ?? address}</dt>
      <dd
        className="num"
        title={v.raw ? t("pdo.live.bytes", { address, raw: v.raw, value: raw }) : undefined}
      >
        {shown}
        {v.text && <span className="pdo-value-text"> · {v.text}</span>}
      </dd>
    </div>
  );
}

function Row({ row }: { row: LivePdo }): ReactNode {
  const { t } = useTranslation();
  return (
    <tr className={row.kind === "rpdo" ? "pdo-live-master" : undefined}>
      <td className="mono">{formatCobId(row.cob_id)}</td>
      <td>{pdoLabel(row)}</td>
      <td className="num">{row.frames}</td>
      <td className="num" data-testid={`rate-${row.cob_id}`}>
        {formatRate(row.rate_hz)}
      </td>
      <td>
        {row.frames === 0 ? (
          <span className="muted small">{t("pdo.live.noneYet")}</span>
        ) : (
          <dl className="pdo-values">
            {row.values.map((v) => (
              <Value key={`${v.index}:${v.subindex}`} value={v} />
            ))}
          </dl>
        )}
      </td>
    </tr>
  );
}

/** After an apply: start the node, give it SYNC if the mapping needs it, and watch the PDOs
 * arrive with their rate and decoded values. */
export function LiveCheck({ node, device }: { node: number; device: readonly Pdo[] }): ReactNode {
  const { t } = useTranslation();
  const live = useLiveCapture(node);
  const needsSync = device.some((p) => p.valid && isSynchronous(p.transmission_type));

  const configure = useMay("configure");
  const startAll = useAction(async () => {
    await call(
      api.POST("/api/nodes/{node}/nmt", {
        params: { path: { node } },
        body: { command: "start" },
      }),
    );
    await live.start();
  });
  const rows = live.capture?.pdos ?? [];
  // TPDOs are what the node sends, so they come first; RPDOs are the master's commands to it
  // (often nothing yet while commissioning), a quieter group whose silent PDOs share one line.
  const sent = rows.filter((r) => r.kind === "tpdo");
  const received = rows.filter((r) => r.kind === "rpdo");
  const seen = received.filter((r) => r.frames > 0);
  const unseen = received.filter((r) => r.frames === 0);

  return (
    <section className="card" aria-labelledby="pdo-live-heading">
      <header className="card-header">
        <h2 id="pdo-live-heading">{t("pdo.live.heading")}</h2>
        <span className="muted small">{t("pdo.live.intro")}</span>
      </header>
      <div className="button-row">
        {live.running ? (
          <button type="button" onClick={() => void live.stop()}>
            {t("pdo.live.stop")}
          </button>
        ) : (
          <button
            type="button"
            className="primary"
            onClick={() => void startAll.run()}
            {...configure.gate(t("pdo.live.gateStart"), { disabled: startAll.busy })}
          >
            {t("pdo.live.start")}
          </button>
        )}
        {live.running && <span className="badge pdo-valid">{t("pdo.live.watching")}</span>}
        {needsSync && <SyncControl />}
        {startAll.busy && <Spinner label={t("pdo.live.starting")} />}
      </div>
      <ErrorText error={startAll.error ?? live.error} />
      {live.capture && (
        <table className="data-table pdo-live-table" aria-label={t("pdo.live.table")}>
          <thead>
            <tr>
              <th>COB-ID</th>
              <th>PDO</th>
              <th>{t("pdo.live.frames")}</th>
              <th>{t("pdo.live.rate")}</th>
              <th>{t("pdo.live.values")}</th>
            </tr>
          </thead>
          <tbody aria-label={t("pdo.live.sentByNode", { node })}>
            <tr className="pdo-live-group">
              <th colSpan={5} scope="colgroup">
                {t("pdo.live.sentByNode", { node })}{" "}
                <span className="muted small">{t("pdo.live.itsTpdos")}</span>
              </th>
            </tr>
            {sent.map((row) => (
              <Row key={row.cob_id} row={row} />
            ))}
            {sent.length === 0 && (
              <tr>
                <td colSpan={5} className="muted">
                  {t("pdo.live.noTpdo")}
                </td>
              </tr>
            )}
          </tbody>
          {received.length > 0 && (
            <tbody className="pdo-live-master" aria-label={t("pdo.live.sentByMaster")}>
              <tr className="pdo-live-group">
                <th colSpan={5} scope="colgroup">
                  {t("pdo.live.sentByMasterTo", { node })}{" "}
                  <span className="muted small">{t("pdo.live.itsRpdos")}</span>
                </th>
              </tr>
              {seen.map((row) => (
                <Row key={row.cob_id} row={row} />
              ))}
              {unseen.length > 0 && (
                <tr>
                  <td colSpan={5} className="muted small">
                    {t("pdo.live.noneFromMaster", {
                      pdos: unseen
                        .map((r) => `${pdoLabel(r)} (${formatCobId(r.cob_id)})`)
                        .join(t("common.listSeparator")),
                    })}
                  </td>
                </tr>
              )}
            </tbody>
          )}
        </table>
      )}
      {live.capture?.drive_page && (
        <p className="muted small" data-testid="pdo-drive-page">
          {live.capture.drive_page}
        </p>
      )}
    </section>
  );
}
