// The one WebSocket to /api/ws: connects, feeds the store, pings every 10 s, notices a dead
// link (no message for a while: the server sends bus status every 2 s) and reconnects with
// backoff. Timers are plain setTimeout/setInterval so tests drive them with fake timers.
import { backoffDelay, DEFAULT_BACKOFF, type BackoffOptions } from "./backoff";
import { parseMessage, type ClientMessage } from "./messages";
import type { LiveStore } from "./store";

/** The part of the browser WebSocket this module uses (tests hand in a fake). */
export interface SocketLike {
  send(data: string): void;
  close(code?: number, reason?: string): void;
  onopen: ((event: Event) => void) | null;
  onmessage: ((event: MessageEvent) => void) | null;
  onclose: ((event: CloseEvent) => void) | null;
  onerror: ((event: Event) => void) | null;
}

export type SocketFactory = (url: string) => SocketLike;

export interface ConnectionOptions {
  url: string;
  createSocket?: SocketFactory;
  pingMs?: number;
  /** Silence longer than this counts as a dead link. */
  staleMs?: number;
  backoff?: BackoffOptions;
  random?: () => number;
  /** Sent first on every connection (the safety layer's hello: who this tab is). */
  hello?: ClientMessage | null;
  /** The server closed with 1008 (policy): no valid login session. Reconnecting goes on;
   * the caller checks the session, which shows the login screen when it is gone. */
  onRefused?: () => void;
}

export const PING_MS = 10_000;
export const STALE_MS = 25_000;

/** ws://host/api/ws for the page's own origin (the dev server proxies it). */
export function liveUrl(location: Pick<Location, "protocol" | "host">): string {
  const scheme = location.protocol === "https:" ? "wss:" : "ws:";
  return `${scheme}//${location.host}/api/ws`;
}

export class LiveConnection {
  private readonly store: LiveStore;
  private readonly options: Required<ConnectionOptions>;
  private socket: SocketLike | null = null;
  private attempt = 0;
  private lastMessageAt = 0;
  private pingTimer: ReturnType<typeof setInterval> | null = null;
  private retryTimer: ReturnType<typeof setTimeout> | null = null;
  private running = false;

  constructor(store: LiveStore, options: ConnectionOptions) {
    this.store = store;
    this.options = {
      createSocket: (url) => new WebSocket(url),
      pingMs: PING_MS,
      staleMs: STALE_MS,
      backoff: DEFAULT_BACKOFF,
      random: Math.random,
      hello: null,
      onRefused: () => undefined,
      ...options,
    };
  }

  start(): void {
    if (this.running) return;
    this.running = true;
    this.open();
  }

  stop(): void {
    this.running = false;
    this.clearTimers();
    this.dropSocket();
    this.store.setLink({ state: "closed", attempt: this.attempt, retryAt: null });
  }

  private open(): void {
    this.retryTimer = null;
    this.store.setLink({ state: "connecting", attempt: this.attempt, retryAt: null });
    let socket: SocketLike;
    try {
      socket = this.options.createSocket(this.options.url);
    } catch {
      // An invalid URL or a browser refusing the socket: treat like a failed attempt.
      this.scheduleRetry();
      return;
    }
    this.socket = socket;
    socket.onopen = () => {
      this.attempt = 0;
      this.lastMessageAt = Date.now();
      if (this.options.hello) socket.send(JSON.stringify(this.options.hello));
      this.store.setLink({ state: "open", attempt: 0, retryAt: null });
      this.pingTimer = setInterval(() => this.tick(), this.options.pingMs);
    };
    socket.onmessage = (event: MessageEvent) => {
      this.lastMessageAt = Date.now();
      if (typeof event.data !== "string") return;
      const message = parseMessage(event.data);
      if (message) this.store.apply(message);
    };
    socket.onclose = (event: CloseEvent) => {
      if (event.code === 1008) this.options.onRefused();
      this.lost();
    };
    socket.onerror = () => undefined; // a close event always follows; handled there
  }

  /** Send one message if the socket is open; false otherwise. */
  send(message: ClientMessage): boolean {
    if (!this.socket || this.store.getSnapshot().link.state !== "open") return false;
    try {
      this.socket.send(JSON.stringify(message));
      return true;
    } catch {
      return false;
    }
  }

  private tick(): void {
    if (Date.now() - this.lastMessageAt > this.options.staleMs) {
      // A half-open TCP link may never deliver a close event: give up on it ourselves.
      this.lost();
      return;
    }
    this.socket?.send(JSON.stringify({ type: "ping" }));
  }

  private lost(): void {
    this.clearTimers();
    this.dropSocket();
    if (this.running) this.scheduleRetry();
  }

  private scheduleRetry(): void {
    const delay = backoffDelay(this.attempt, this.options.backoff, this.options.random);
    this.attempt += 1;
    this.store.setLink({ state: "closed", attempt: this.attempt, retryAt: Date.now() + delay });
    this.retryTimer = setTimeout(() => this.open(), delay);
  }

  private dropSocket(): void {
    const socket = this.socket;
    this.socket = null;
    if (!socket) return;
    // Detach first so the close we cause is not reported as a lost link a second time.
    socket.onopen = null;
    socket.onmessage = null;
    socket.onclose = null;
    socket.onerror = null;
    try {
      socket.close();
    } catch {
      // Closing a socket that never opened can throw in some browsers; it is gone either way.
    }
  }

  private clearTimers(): void {
    if (this.pingTimer !== null) clearInterval(this.pingTimer);
    if (this.retryTimer !== null) clearTimeout(this.retryTimer);
    this.pingTimer = null;
    this.retryTimer = null;
  }
}
