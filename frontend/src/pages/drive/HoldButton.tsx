import { useEffect, useRef, useState, type ReactNode } from "react";

import { HoldToRun, type HoldSnapshot, type HoldTransport } from "./holdToRun";

/**
 * A hold-to-run button: pointer down starts, pointer up / leave / cancel, the window losing
 * focus, the page being hidden or the component going away stop. No pointer capture on
 * purpose: sliding off the button is letting go. Keyboard: Space or Enter
 * held down runs, released stops (a key repeat does not restart).
 */
export function HoldButton({
  label,
  transport,
  disabled,
  onChange,
  className,
  title,
}: {
  label: string;
  /** Why it is disabled, when it is. */
  title?: string;
  transport: HoldTransport;
  disabled?: boolean;
  onChange?: (snapshot: HoldSnapshot) => void;
  className?: string;
}): ReactNode {
  const transportRef = useRef(transport);
  const onChangeRef = useRef(onChange);
  useEffect(() => {
    transportRef.current = transport;
    onChangeRef.current = onChange;
  });
  const [phase, setPhase] = useState<HoldSnapshot["phase"]>("idle");
  const holdRef = useRef<HoldToRun | null>(null);

  // One controller per mounted button; the transport is looked up per call, so a changed
  // speed applies to the next press without a new controller.
  useEffect(() => {
    const hold = new HoldToRun(
      {
        start: () => transportRef.current.start(),
        keepalive: (id) => transportRef.current.keepalive(id),
        stop: (id) => transportRef.current.stop(id),
      },
      {
        onChange: (snapshot) => {
          setPhase(snapshot.phase);
          onChangeRef.current?.(snapshot);
        },
      },
    );
    holdRef.current = hold;
    const stop = (): void => hold.release();
    const hidden = (): void => {
      if (document.visibilityState === "hidden") hold.release();
    };
    window.addEventListener("blur", stop);
    document.addEventListener("visibilitychange", hidden);
    return () => {
      window.removeEventListener("blur", stop);
      document.removeEventListener("visibilitychange", hidden);
      hold.release();
      holdRef.current = null;
    };
  }, []);

  useEffect(() => {
    if (disabled) holdRef.current?.release();
  }, [disabled]);

  const press = (): void => holdRef.current?.press();
  const release = (): void => holdRef.current?.release();
  const active = phase !== "idle";
  return (
    <button
      type="button"
      className={`hold-button${active ? " held" : ""}${className ? ` ${className}` : ""}`}
      disabled={disabled}
      title={title}
      aria-pressed={active}
      onPointerDown={(e) => {
        if (e.button !== 0) return;
        press();
      }}
      onPointerUp={() => release()}
      onPointerCancel={() => release()}
      onPointerLeave={() => release()}
      onKeyDown={(e) => {
        if ((e.key === " " || e.key === "Enter") && !e.repeat) {
          e.preventDefault();
          press();
        }
      }}
      onKeyUp={(e) => {
        if (e.key === " " || e.key === "Enter") release();
      }}
      onBlur={() => release()}
      onContextMenu={(e) => e.preventDefault()}
    >
      {label}
    </button>
  );
}
