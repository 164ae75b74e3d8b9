import { useEffect, useMemo, useRef, useState, type ReactNode } from "react";

import { asApiError, type ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useAction, useApi } from "../../lib/useApi";
import { usePoll } from "../../lib/usePoll";
import { useLive } from "../../live/context";
import { useMay } from "../../session/context";
import { CaptureCard } from "./CaptureCard";
import { CaptureList } from "./CaptureList";
import { CaptureSettings } from "./CaptureSettings";
import { loadForm, saveForm } from "./formStore";
import { asRequest, hasWord, loadLanes, saveLanes } from "./lanes";
import { LaneSettings } from "./LaneSettings";
import { MeasurePanel } from "./MeasurePanel";
import { buildRequest, isActive, startReason } from "./model";
import { PlanView } from "./PlanView";
import "./scope.css";
import { getCapture, listCaptures, startCapture, stopOrDeleteCapture } from "./scopeApi";
import { SignalPicker } from "./SignalPicker";
import { EMPTY_HISTORY, pushHistory, type History } from "./sparkline";
import type { Capture } from "./types";
import { usePlan } from "./usePlan";
import { ViewerPanel, type OpenedCapture } from "./ViewerPanel";

const POLL_MS = 250; // the active capture, ~4 per second
const SERIES_WAIT_S = 5; // normal mode: how long to look for the re-armed capture

/** The live scope: pick signals, check the plan, start, follow it, and the captures kept. */
export function ScopePage(): ReactNode {
  const { t } = useTranslation();
  const nodes = useLive((s) => s.infos);
  const [form, setForm] = useState(loadForm);
  useEffect(() => saveForm(form), [form]);
  const [lanes, setLanes] = useState(loadLanes);
  useEffect(() => saveLanes(lanes), [lanes]);
  // What keeps the form from being sent, built at every render so it follows the language; the
  // request itself only when the form changes (the plan check runs again for a new request).
  const built = buildRequest(form);
  const request = useMemo(() => {
    const fresh = buildRequest(form);
    return fresh.ok ? fresh.request : null;
  }, [form]);
  const [refresh, setRefresh] = useState(0);

  const list = useApi((signal) => listCaptures(signal), "scope-captures");
  const [followed, setFollowed] = useState<Capture | null>(null);
  const [history, setHistory] = useState<History>(EMPTY_HISTORY);
  const [now, setNow] = useState(() => Date.now() / 1000);
  const [pollError, setPollError] = useState<ApiError | null>(null);
  const [opened, setOpened] = useState<OpenedCapture | null>(null);
  const [stopped, setStopped] = useState<ReadonlySet<number>>(() => new Set());
  const polling = useRef(false);
  // bumped by every stop: a poll sent before it may answer after the stop's own answer, with
  // the capture still recording; that answer is dropped (it would show "Recording" again)
  const stops = useRef(0);
  // captures the user stopped: a poll that still says recording is older than the stop (a
  // stopped capture never records again), whenever it was sent
  const stoppedIds = useRef(new Set<number>());

  // The capture shown: the one this page follows, or one the list shows recording (started
  // before the page opened, or the next of a re-armed series).
  const listActive = list.data?.find(isActive) ?? null;
  const current =
    followed && (isActive(followed) || listActive === null || listActive.id === followed.id)
      ? followed
      : (listActive ?? followed);
  const active = isActive(current);
  const seriesWaiting =
    !active &&
    current?.state === "done" &&
    current.trigger.mode === "normal" &&
    !stopped.has(current.id) &&
    now - (current.ended ?? now) < SERIES_WAIT_S;

  const plan = usePlan(request, {
    refresh,
    paused: active || seriesWaiting,
  });

  const follow = (capture: Capture): void => {
    setFollowed(capture);
    setHistory((old) => pushHistory(old, capture));
    setNow(Date.now() / 1000);
  };

  const ended = (): void => {
    list.reload();
    setRefresh((n) => n + 1); // the scope's TPDOs are free again
  };

  usePoll(
    () => {
      if (!current || polling.current) return;
      polling.current = true;
      const sent = stops.current;
      getCapture(current.id).then(
        (capture) => {
          polling.current = false;
          if (sent !== stops.current) return; // overtaken by a stop
          if (isActive(capture) && stoppedIds.current.has(capture.id)) return;
          setPollError(null);
          follow(capture);
          if (!isActive(capture)) ended();
        },
        (error: unknown) => {
          polling.current = false;
          setPollError(asApiError(error));
        },
      );
    },
    POLL_MS,
    active,
  );
  usePoll(
    () => {
      list.reload();
      setNow(Date.now() / 1000);
    },
    500,
    seriesWaiting,
  );

  const start = useAction(async () => {
    if (request === null) return;
    const capture = await startCapture({ ...request, lanes: asRequest(lanes) });
    setHistory(EMPTY_HISTORY);
    follow(capture);
    setOpened(null); // the live view shows it
    list.reload();
  });
  const stop = useAction(async () => {
    if (!current) return;
    const id = current.id;
    stops.current += 1;
    stoppedIds.current.add(id);
    setStopped((old) => new Set(old).add(id));
    const capture = await stopOrDeleteCapture(id);
    if (capture) follow(capture);
    ended();
  });

  const operate = useMay("operate");
  const reason = operate.because(t("scope.page.gateStart")) ?? startReason(built, plan, current);
  const rows = useMemo(() => {
    const captures = list.data;
    if (!captures || !current) return captures;
    const merged = captures.map((c) => (c.id === current.id ? current : c));
    return merged.some((c) => c.id === current.id) ? merged : [current, ...merged];
  }, [list.data, current]);
  // the cursors sit on the capture opened in the viewer, else the newest finished one
  const measured =
    rows?.find((c) => c.id === opened?.id && c.state === "done") ??
    rows?.find((c) => c.state === "done") ??
    null;

  return (
    <section className="page scope-page">
      <header className="page-header">
        <h1>{t("scope.page.title")}</h1>
        <span className="muted">{t("scope.page.subtitle")}</span>
      </header>
      <div className="scope-top">
        <div className="scope-column">
          <SignalPicker
            nodes={nodes}
            signals={form.signals}
            onChange={(signals) => setForm((old) => ({ ...old, signals }))}
          />
          {hasWord(
            form.signals.map((s) => s.index),
            form.trigger.kind,
          ) && <LaneSettings lanes={lanes} onChange={setLanes} />}
          <CaptureSettings
            form={form}
            nodes={nodes}
            planned={plan.plan?.signals ?? []}
            onChange={setForm}
          />
        </div>
        <div className="scope-column">
          <PlanView
            plan={plan.plan}
            checking={plan.checking}
            error={plan.error}
            problem={built.ok ? null : built.problem}
            paused={active || seriesWaiting}
          >
            <div className="button-row scope-start">
              <button
                type="button"
                className="primary"
                disabled={reason !== null || start.busy}
                title={reason ?? undefined}
                aria-describedby={reason ? "scope-start-reason" : undefined}
                onClick={() => void start.run()}
              >
                {t("scope.page.start")}
              </button>
              {start.busy && <Spinner label={t("scope.page.starting")} />}
              {reason && (
                <span id="scope-start-reason" className="muted small">
                  {reason}
                </span>
              )}
            </div>
            <ErrorText error={start.error} onRetry={() => setRefresh((n) => n + 1)} />
          </PlanView>
          {current && (
            <CaptureCard
              capture={current}
              history={history}
              now={now}
              onStop={() => void stop.run()}
              stopping={stop.busy}
              error={stop.error ?? pollError}
            />
          )}
        </div>
      </div>
      <ViewerPanel opened={opened} onLive={() => setOpened(null)} />
      {measured && <MeasurePanel key={measured.id} capture={measured} />}
      <CaptureList
        captures={rows}
        loading={list.loading}
        error={list.error}
        onReload={list.reload}
        onOpen={(capture) =>
          setOpened((old) => ({
            id: capture.id,
            name: capture.name,
            nonce: (old?.nonce ?? 0) + 1,
          }))
        }
        onDeleted={(id) => {
          if (opened?.id === id) setOpened(null);
          if (followed?.id === id) setFollowed(null);
          list.reload();
        }}
      />
    </section>
  );
}
