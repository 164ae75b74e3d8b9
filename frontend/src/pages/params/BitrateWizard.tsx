import { useId, useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import type { BitrateChangeResult, BitrateOptions } from "../../api/types";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { formatBitrate } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useLive, useLiveStore } from "../../live/context";
import { useMay } from "../../session/context";

/** Change the node's CAN bitrate, then offer to reconnect the tool at the new rate. Only the
 * rates the node's profile can set are offered; a drive that sets its bitrate elsewhere says
 * so instead of offering a change that cannot succeed. */
export function BitrateWizard({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const selectId = useId();
  const store = useLiveStore();
  const bus = useLive((s) => s.bus);
  const [open, setOpen] = useState(false);
  const [bitrate, setBitrate] = useState(String(bus?.bitrate ?? 500_000));
  const [result, setResult] = useState<BitrateChangeResult | null>(null);
  const [options, setOptions] = useState<BitrateOptions | null>(null);
  const fetchOptions = useAction(async () => {
    const answer = await call(
      api.GET("/api/nodes/{node}/bitrates", { params: { path: { node } } }),
    );
    setOptions(answer);
    const current = answer.current ?? bus?.bitrate;
    const other = answer.supported.find((rate) => rate !== current);
    if (other !== undefined) setBitrate(String(other));
  });
  const change = useAction(async () => {
    setResult(
      await call(
        api.POST("/api/nodes/{node}/change-bitrate", {
          params: { path: { node } },
          body: { bitrate: Number(bitrate), confirm: true },
        }),
      ),
    );
  });
  const reconnect = useAction(async (rate: number) => {
    const status = await call(
      api.POST("/api/bus/connect", {
        body: {
          interface: bus?.interface ?? null,
          channel: bus?.channel ?? null,
          bitrate: rate,
          options: {},
          simulated: bus?.simulated ?? false,
        },
      }),
    );
    store.apply({ type: "bus", bus: status });
    if (status.state === "connected") setOpen(false);
  });

  const configure = useMay("configure");

  function close(): void {
    setOpen(false);
    setResult(null);
    setOptions(null);
  }

  const title = t("params.bitrate.title", { node });
  return (
    <>
      <button
        type="button"
        onClick={() => {
          setOpen(true);
          void fetchOptions.run();
        }}
        {...configure.gate(t("params.bitrate.gate"))}
      >
        {t("params.bitrate.open")}
      </button>
      {open && !result && options && !options.settable && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <button type="button" onClick={close}>
              {t("params.close")}
            </button>
          }
        >
          <p role="status">{options.note}</p>
          <p>{t("params.bitrate.elsewhere")}</p>
        </Dialog>
      )}
      {open && !result && !options && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <button type="button" onClick={close}>
              {t("params.cancel")}
            </button>
          }
        >
          {fetchOptions.busy && <Spinner label={t("params.bitrate.reading")} />}
          <ErrorText error={fetchOptions.error} onRetry={() => void fetchOptions.run()} />
        </Dialog>
      )}
      {open && !result && options?.settable && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <>
              <button type="button" onClick={close}>
                {t("params.cancel")}
              </button>
              <button
                type="button"
                className="primary"
                disabled={change.busy}
                onClick={() => void change.run()}
              >
                {t("params.bitrate.submit")}
              </button>
              {change.busy && <Spinner label={t("params.bitrate.changing")} />}
            </>
          }
        >
          <label htmlFor={selectId}>{t("params.bitrate.label")}</label>
          <select id={selectId} value={bitrate} onChange={(e) => setBitrate(e.target.value)}>
            {options.supported.map((rate) => (
              <option key={rate} value={String(rate)}>
                {rate === options.current
                  ? t("params.bitrate.now", { rate: formatBitrate(rate) })
                  : formatBitrate(rate)}
              </option>
            ))}
          </select>
          <p className="muted small">{options.note}</p>
          <p>{t("params.bitrate.serverWill")}</p>
          <p>
            {bus?.bitrate
              ? t("params.bitrate.disappearsNow", {
                  node,
                  rate: formatBitrate(Number(bitrate)),
                  now: formatBitrate(bus.bitrate),
                })
              : t("params.bitrate.disappears", { node, rate: formatBitrate(Number(bitrate)) })}
          </p>
          <ErrorText error={change.error} />
        </Dialog>
      )}
      {open && result && (
        <Dialog
          title={t("params.bitrate.changed")}
          onClose={close}
          actions={
            <>
              <button type="button" onClick={close}>
                {t("params.bitrate.later")}
              </button>
              <button
                type="button"
                className="primary"
                disabled={reconnect.busy}
                onClick={() => void reconnect.run(result.bitrate)}
              >
                {t("params.bitrate.reconnect", { rate: formatBitrate(result.bitrate) })}
              </button>
              {reconnect.busy && <Spinner label={t("params.bitrate.reconnecting")} />}
            </>
          }
        >
          <ol className="steps">
            {result.steps.map((step, i) => (
              <li key={i}>{step}</li>
            ))}
          </ol>
          <p>{t("params.bitrate.nowUses", { rate: formatBitrate(result.bitrate) })}</p>
          <ErrorText error={reconnect.error} />
        </Dialog>
      )}
    </>
  );
}
