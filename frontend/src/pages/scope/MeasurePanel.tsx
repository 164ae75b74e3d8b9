import { useEffect, useId, useRef, useState, type KeyboardEvent, type ReactNode } from "react";

import { asApiError, type ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { odAddress } from "../../lib/format";
import { useApi } from "../../lib/useApi";
import {
  formatDuration,
  formatNumber,
  initialCursors,
  nearestCursor,
  nudge,
  parseCursor,
  readoutRows,
  stepOf,
  timeAt,
  xAt,
  type CursorName,
  type Cursors,
  type Span,
} from "./measure";
import { measureCapture, traceCapture } from "./scopeApi";
import { envelopePath } from "./sparkline";
import type { Capture, Measurement } from "./types";

const WIDTH = 800; // the overview's drawing units; CSS stretches it to the panel
const HEIGHT = 90;
const POINTS = 400;
const DEBOUNCE_MS = 120; // a drag asks the server at most this often

/** Cursors A and B on a finished capture and the readout between them (Δt, and per signal
 * the values at A and B, Δ, min, max, mean): set by dragging on the overview of one signal,
 * by ←/→ on a focused cursor, or by typing the times. */
export function MeasurePanel({ capture }: { capture: Capture }): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const [position, setPosition] = useState(0);
  const trace = useApi(
    (signal) => traceCapture(capture.id, position, POINTS, signal),
    `scope-trace-${capture.id}-${position}`,
  );
  const span: Span | null = trace.data ? { start: trace.data.start, end: trace.data.end } : null;
  const [cursors, setCursors] = useState<{ capture: number; at: Cursors } | null>(null);
  const at = cursors?.capture === capture.id ? cursors.at : span ? initialCursors(span) : null;
  const move = (name: CursorName, time: number): void => {
    if (!at) return;
    setCursors({ capture: capture.id, at: { ...at, [name]: time } });
  };
  const measurement = useMeasurement(capture.id, at);

  return (
    <section className="card scope-measure" aria-labelledby={`${id}-h`}>
      <header className="card-header">
        <h2 id={`${id}-h`}>{t("scope.measure.heading")}</h2>
        <span className="muted small">
          {t("scope.measure.hint", {
            name: capture.name ?? t("scope.measure.captureN", { id: capture.id }),
          })}
        </span>
        {(trace.loading || measurement.busy) && <Spinner label={t("scope.measure.measuring")} />}
      </header>
      <div className="scope-measure-controls">
        <label>
          {t("scope.measure.overviewOf")}{" "}
          <select value={position} onChange={(e) => setPosition(Number(e.target.value))}>
            {capture.signals.map((s, i) => (
              <option key={`${s.node}:${s.index}:${s.subindex}`} value={i}>
                {t("scope.measure.signalOption", {
                  node: s.node,
                  address: odAddress(s.index, s.subindex),
                  name: s.name,
                })}
              </option>
            ))}
          </select>
        </label>
        {span && at && (
          <>
            <CursorInput name="a" label="A" value={at.a} span={span} onChange={move} />
            <CursorInput name="b" label="B" value={at.b} span={span} onChange={move} />
            <span className="scope-measure-dt" aria-live="polite">
              Δt = <strong>{formatDuration(at.b - at.a)}</strong>
            </span>
          </>
        )}
      </div>
      <ErrorText error={trace.error} onRetry={trace.reload} />
      {trace.data && span && at && (
        <Overview
          path={envelopePath(trace.data, span, WIDTH, HEIGHT)}
          span={span}
          cursors={at}
          label={t("scope.measure.overviewLabel", {
            signal: capture.signals[position]?.name ?? t("scope.measure.signalFallback"),
          })}
          onMove={move}
        />
      )}
      <ErrorText error={measurement.error} />
      {measurement.data && <Readout measurement={measurement.data} />}
    </section>
  );
}

function useMeasurement(
  captureId: number,
  at: Cursors | null,
): { data: Measurement | null; error: ApiError | null; busy: boolean } {
  const [state, setState] = useState<{ data: Measurement | null; error: ApiError | null }>({
    data: null,
    error: null,
  });
  const [busy, setBusy] = useState(false);
  const a = at?.a;
  const b = at?.b;
  useEffect(() => {
    if (a === undefined || b === undefined) return;
    const controller = new AbortController();
    const timer = setTimeout(() => {
      setBusy(true);
      measureCapture(captureId, a, b, controller.signal).then(
        (data) => {
          setBusy(false);
          setState({ data, error: null });
        },
        (error: unknown) => {
          if (controller.signal.aborted) return;
          setBusy(false);
          setState((old) => ({ data: old.data, error: asApiError(error) }));
        },
      );
    }, DEBOUNCE_MS);
    return () => {
      clearTimeout(timer);
      controller.abort();
    };
  }, [captureId, a, b]);
  return { ...state, busy };
}

function CursorInput({
  name,
  label,
  value,
  span,
  onChange,
}: {
  name: CursorName;
  label: string;
  value: number;
  span: Span;
  onChange: (name: CursorName, t: number) => void;
}): ReactNode {
  const [text, setText] = useState<string | null>(null);
  const parsed = text === null ? value : parseCursor(text, span);
  const problem = typeof parsed === "string" ? parsed : null;
  const errorId = useId();
  const commit = (): void => {
    if (typeof parsed === "number") onChange(name, parsed);
    setText(null);
  };
  return (
    <label className={`scope-cursor-input cursor-${name}`}>
      {label} [s]{" "}
      <input
        type="number"
        step={stepOf(span)}
        min={span.start}
        max={span.end}
        value={text ?? formatNumber(value)}
        aria-invalid={problem !== null}
        aria-describedby={problem ? errorId : undefined}
        onChange={(e) => {
          setText(e.target.value);
          const next = parseCursor(e.target.value, span);
          if (typeof next === "number") onChange(name, next);
        }}
        onBlur={commit}
        onKeyDown={(e) => {
          if (e.key === "Enter") commit();
        }}
      />
      {problem && (
        <span id={errorId} className="error small">
          {problem}
        </span>
      )}
    </label>
  );
}

function Overview({
  path,
  span,
  cursors,
  label,
  onMove,
}: {
  path: string;
  span: Span;
  cursors: Cursors;
  label: string;
  onMove: (name: CursorName, t: number) => void;
}): ReactNode {
  const { t } = useTranslation();
  const svg = useRef<SVGSVGElement>(null);
  const dragging = useRef<CursorName | null>(null);
  const timeOf = (clientX: number): number => {
    const box = svg.current?.getBoundingClientRect();
    if (!box || box.width === 0) return span.start;
    return timeAt(((clientX - box.left) / box.width) * WIDTH, WIDTH, span);
  };
  const keys = (name: CursorName) => (e: KeyboardEvent<SVGGElement>) => {
    const next = nudge(cursors[name], e.key, e.shiftKey, span);
    if (next === null) return;
    e.preventDefault();
    onMove(name, next);
  };
  return (
    <svg
      ref={svg}
      className="scope-overview"
      viewBox={`0 0 ${WIDTH} ${HEIGHT}`}
      preserveAspectRatio="none"
      role="group"
      aria-label={label}
      onPointerDown={(e) => {
        const time = timeOf(e.clientX);
        const name = nearestCursor(cursors, time);
        dragging.current = name;
        e.currentTarget.setPointerCapture(e.pointerId);
        onMove(name, time);
      }}
      onPointerMove={(e) => {
        if (dragging.current) onMove(dragging.current, timeOf(e.clientX));
      }}
      onPointerUp={() => {
        dragging.current = null;
      }}
    >
      <path d={path} className="scope-overview-band" />
      {(["a", "b"] as const).map((name) => {
        const x = xAt(cursors[name], WIDTH, span);
        return (
          <g
            key={name}
            className={`scope-cursor cursor-${name}`}
            tabIndex={0}
            role="slider"
            aria-label={t("scope.measure.cursor", { name: name.toUpperCase() })}
            aria-valuemin={span.start}
            aria-valuemax={span.end}
            aria-valuenow={cursors[name]}
            aria-valuetext={`${formatNumber(cursors[name])} s`}
            onKeyDown={keys(name)}
          >
            <line x1={x} x2={x} y1={0} y2={HEIGHT} vectorEffect="non-scaling-stroke" />
            <rect x={x - 6} y={0} width={12} height={14} />
            <text x={x} y={11} textAnchor="middle">
              {name.toUpperCase()}
            </text>
          </g>
        );
      })}
    </svg>
  );
}

function Readout({ measurement }: { measurement: Measurement }): ReactNode {
  const { t } = useTranslation();
  return (
    <div className="table-scroll">
      <table className="data-table scope-readout" aria-label={t("scope.measure.readout")}>
        <thead>
          <tr>
            <th>{t("scope.measure.signal")}</th>
            <th>{t("scope.measure.unit")}</th>
            <th>{t("scope.measure.atA")}</th>
            <th>{t("scope.measure.atB")}</th>
            <th>{t("scope.measure.delta")}</th>
            <th>{t("scope.measure.min")}</th>
            <th>{t("scope.measure.max")}</th>
            <th>{t("scope.measure.mean")}</th>
            <th>{t("scope.measure.samples")}</th>
          </tr>
        </thead>
        <tbody>
          {readoutRows(measurement).map((row) => (
            <tr key={row.key}>
              <td>{row.signal}</td>
              <td>{row.unit}</td>
              <td className="num">{row.a}</td>
              <td className="num">{row.b}</td>
              <td className="num">{row.delta}</td>
              <td className="num">{row.min}</td>
              <td className="num">{row.max}</td>
              <td className="num">{row.mean}</td>
              <td className="num">{row.count}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
