// Hold-to-run: the axis moves only while the button is held. Press starts a jog on the server
// and sends a keep-alive every ~100 ms (the server stops the axis when they stop for its
// keepalive_ms); release, a lost pointer, a blurred window or a hidden page stop it. A release
// that comes before the server has answered the start still stops the jog the moment its id
// arrives. Plain timers and injected transport, so tests drive it with fake timers.

export const KEEPALIVE_INTERVAL_MS = 100;
export const KEEPALIVE_TIMEOUT_MS = 300;

export type HoldPhase = "idle" | "starting" | "running";

export interface HoldSnapshot {
  phase: HoldPhase;
  jogId: string | null;
  /** Why the last hold ended on its own (the server refused or dropped the jog). */
  error: string | null;
}

export interface HoldTransport {
  /** Start the jog; resolves with its id. */
  start: () => Promise<string>;
  /** One keep-alive; a rejection means the jog is gone (the server stopped it). */
  keepalive: (jogId: string) => Promise<void> | void;
  stop: (jogId: string) => Promise<void> | void;
}

export interface HoldOptions {
  intervalMs?: number;
  onChange?: (snapshot: HoldSnapshot) => void;
}

function message(error: unknown): string {
  if (error instanceof Error) return error.message;
  return String(error);
}

export class HoldToRun {
  private snapshot: HoldSnapshot = { phase: "idle", jogId: null, error: null };
  private timer: ReturnType<typeof setInterval> | null = null;
  /** Bumped on every press and release: a late answer of an old press is recognised. */
  private generation = 0;
  private readonly intervalMs: number;

  constructor(
    private readonly transport: HoldTransport,
    private readonly options: HoldOptions = {},
  ) {
    this.intervalMs = options.intervalMs ?? KEEPALIVE_INTERVAL_MS;
  }

  get state(): HoldSnapshot {
    return this.snapshot;
  }

  /** Button pressed. Ignored while a hold is already in progress. */
  press(): void {
    if (this.snapshot.phase === "starting" || this.snapshot.phase === "running") return;
    this.generation += 1;
    const generation = this.generation;
    this.set({ phase: "starting", jogId: null, error: null });
    let started: Promise<string>;
    try {
      started = this.transport.start();
    } catch (error) {
      this.set({ phase: "idle", jogId: null, error: message(error) });
      return;
    }
    started.then(
      (jogId) => {
        if (generation !== this.generation) {
          // released (or superseded) before the server answered: stop what just started
          void this.safeStop(jogId);
          return;
        }
        this.set({ phase: "running", jogId, error: null });
        this.timer = setInterval(() => this.beat(generation, jogId), this.intervalMs);
      },
      (error: unknown) => {
        if (generation !== this.generation) return;
        this.set({ phase: "idle", jogId: null, error: message(error) });
      },
    );
  }

  /** Button released, pointer lost, window blurred, page hidden, component unmounted. */
  release(): void {
    this.generation += 1;
    this.clearTimer();
    const { jogId, phase } = this.snapshot;
    if (phase === "idle") return;
    this.set({ phase: "idle", jogId: null, error: this.snapshot.error });
    if (jogId !== null) void this.safeStop(jogId);
  }

  private beat(generation: number, jogId: string): void {
    if (generation !== this.generation) return;
    let sent: Promise<void> | void;
    try {
      sent = this.transport.keepalive(jogId);
    } catch (error) {
      this.lost(generation, error);
      return;
    }
    if (sent) sent.catch((error: unknown) => this.lost(generation, error));
  }

  /** The server no longer knows the jog: the axis has been stopped there. */
  private lost(generation: number, error: unknown): void {
    if (generation !== this.generation) return;
    this.generation += 1;
    this.clearTimer();
    this.set({ phase: "idle", jogId: null, error: message(error) });
  }

  private async safeStop(jogId: string): Promise<void> {
    try {
      await this.transport.stop(jogId);
    } catch {
      // The server stops a jog without keep-alives by itself; nothing more to do here.
    }
  }

  private clearTimer(): void {
    if (this.timer !== null) clearInterval(this.timer);
    this.timer = null;
  }

  private set(snapshot: HoldSnapshot): void {
    this.snapshot = snapshot;
    this.options.onChange?.(snapshot);
  }
}
