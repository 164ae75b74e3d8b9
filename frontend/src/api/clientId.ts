// This tab's identity towards the server's safety layer: sent as `X-Client-Id` on REST calls
// and in the WebSocket hello, so the server knows which tab holds a drive's control and whose
// jogs to stop when the tab's socket closes or its page is hidden. One per page load (a
// reloaded tab is a new client: it has to take control again, deliberately).

function randomId(): string {
  const crypto = globalThis.crypto as Crypto | undefined;
  if (crypto && typeof crypto.randomUUID === "function") return crypto.randomUUID();
  return `${Date.now().toString(36)}-${Math.random().toString(36).slice(2, 10)}`;
}

export const CLIENT_ID: string = randomId();

/** What other users read in "controlled by …". */
export function clientName(): string {
  const agent = typeof navigator === "undefined" ? "" : navigator.userAgent;
  const browser = /Firefox\//.test(agent)
    ? "Firefox"
    : /Edg\//.test(agent)
      ? "Edge"
      : /Chrom(e|ium)\//.test(agent)
        ? "Chrome"
        : /Safari\//.test(agent)
          ? "Safari"
          : "Browser";
  return `${browser} tab ${CLIENT_ID.slice(0, 4)}`;
}

/** Headers for a REST call that the safety layer attributes to this tab. */
export function clientHeaders(): { "X-Client-Id": string; "X-Client-Name": string } {
  return { "X-Client-Id": CLIENT_ID, "X-Client-Name": clientName() };
}
