import { useId, useState, type SubmitEvent, type ReactNode } from "react";

import { api, call } from "../../api/client";
import type { BusConfig, BusStatus } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { formatBitrate } from "../../lib/format";
import { useAction, useApi } from "../../lib/useApi";
import { useLiveStore } from "../../live/context";
import { useMay } from "../../session/context";
import { parseBusOptions } from "./busOptions";

// CiA 301 bit timing table (plus 800k, which CiA 301 lists as well).
export const BITRATES = [
  10_000, 20_000, 50_000, 100_000, 125_000, 250_000, 500_000, 800_000, 1_000_000,
];
const CUSTOM = "custom";

/** Connect the tool to a CAN interface, or to the built-in simulated drives. */
export function ConnectForm({
  bus,
  onConnected,
}: {
  bus: BusStatus | null;
  onConnected: () => void;
}): ReactNode {
  const { t } = useTranslation();
  const ids = {
    iface: useId(),
    channel: useId(),
    bitrate: useId(),
    custom: useId(),
    options: useId(),
  };
  const store = useLiveStore();
  const interfaces = useApi(
    (signal) => call(api.GET("/api/bus/interfaces", { signal })),
    "interfaces",
  );
  const [simulated, setSimulated] = useState(bus?.simulated ?? true);
  const [iface, setIface] = useState(bus?.simulated === false ? (bus.interface ?? "") : "");
  const [channel, setChannel] = useState(bus?.simulated === false ? (bus.channel ?? "") : "");
  const initialRate = bus?.bitrate ?? 500_000;
  const [rateChoice, setRateChoice] = useState(
    BITRATES.includes(initialRate) ? String(initialRate) : CUSTOM,
  );
  const [customRate, setCustomRate] = useState(
    BITRATES.includes(initialRate) ? "" : String(initialRate),
  );
  const [optionsText, setOptionsText] = useState("");
  const [formError, setFormError] = useState<string | null>(null);

  const list = interfaces.data ?? [];
  const chosen = list.find((i) => i.name === iface) ?? list[0];
  const configure = useMay("configure");
  const connect = useAction(async (config: BusConfig) => {
    const status = await call(api.POST("/api/bus/connect", { body: config }));
    store.apply({ type: "bus", bus: status });
    if (status.state === "connected") onConnected();
  });

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    setFormError(null);
    const bitrate = rateChoice === CUSTOM ? Number(customRate) : Number(rateChoice);
    if (!Number.isInteger(bitrate) || bitrate < 1000 || bitrate > 1_000_000) {
      setFormError(t("network.connect.badBitrate"));
      return;
    }
    if (simulated) {
      void connect.run({ simulated: true, bitrate, options: {} });
      return;
    }
    if (!chosen) {
      setFormError(t("network.connect.chooseInterface"));
      return;
    }
    const options = parseBusOptions(optionsText);
    if (!options.ok) {
      setFormError(options.error);
      return;
    }
    if (chosen.needs_channel && !channel.trim()) {
      setFormError(
        t("network.connect.needsChannel", {
          interface: chosen.label,
          example: chosen.example_channel,
        }),
      );
      return;
    }
    void connect.run({
      interface: chosen.name,
      channel: channel.trim() || null,
      bitrate,
      options: options.options,
      simulated: false,
    });
  }

  return (
    <form className="connect-form" onSubmit={submit} aria-label={t("network.connect.heading")}>
      <h3>{t("network.connect.heading")}</h3>
      <label className="check">
        <input
          type="checkbox"
          checked={simulated}
          onChange={(e) => setSimulated(e.target.checked)}
        />
        {t("network.connect.simulated")}
      </label>
      {simulated && <p className="muted small">{t("network.connect.simulatedNote")}</p>}
      <div className="form-grid">
        {!simulated && (
          <>
            <label htmlFor={ids.iface}>{t("network.connect.interface")}</label>
            <select
              id={ids.iface}
              value={chosen?.name ?? ""}
              onChange={(e) => setIface(e.target.value)}
            >
              {list.map((i) => (
                <option key={i.name} value={i.name}>
                  {i.label}
                </option>
              ))}
            </select>
            <label htmlFor={ids.channel}>{t("network.connect.channel")}</label>
            <input
              id={ids.channel}
              value={channel}
              placeholder={chosen?.example_channel ?? ""}
              onChange={(e) => setChannel(e.target.value)}
            />
          </>
        )}
        <label htmlFor={ids.bitrate}>{t("network.connect.bitrate")}</label>
        <span className="inline">
          <select
            id={ids.bitrate}
            value={rateChoice}
            onChange={(e) => setRateChoice(e.target.value)}
          >
            {BITRATES.map((rate) => (
              <option key={rate} value={String(rate)}>
                {formatBitrate(rate)}
              </option>
            ))}
            <option value={CUSTOM}>{t("network.connect.custom")}</option>
          </select>
          {rateChoice === CUSTOM && (
            <input
              id={ids.custom}
              className="narrow"
              inputMode="numeric"
              aria-label={t("network.connect.customLabel")}
              value={customRate}
              placeholder="bit/s"
              onChange={(e) => setCustomRate(e.target.value)}
            />
          )}
        </span>
        {!simulated && (
          <>
            <label htmlFor={ids.options}>{t("network.connect.options")}</label>
            <textarea
              id={ids.options}
              rows={2}
              value={optionsText}
              placeholder={t("network.connect.optionsPlaceholder")}
              onChange={(e) => setOptionsText(e.target.value)}
            />
          </>
        )}
      </div>
      <div className="button-row">
        <button
          type="submit"
          className="primary"
          {...configure.gate(t("network.gate.connect"), { disabled: connect.busy })}
        >
          {t("network.connect.submit")}
        </button>
        {connect.busy && <Spinner label={t("network.connect.busy")} />}
      </div>
      <ErrorText error={formError} />
      <ErrorText error={connect.error ?? interfaces.error} />
    </form>
  );
}
