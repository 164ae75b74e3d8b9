import { render, screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { useState, type ReactNode } from "react";
import { MemoryRouter, useLocation } from "react-router";
import { afterEach, describe, expect, it, vi } from "vitest";

import { api, call } from "../api/client";
import { json, stubFetch } from "../test/fetchStub";
import { sessionAs } from "../test/render";
import { useSession } from "./context";
import { permit } from "./permit";
import { SessionBadge } from "./SessionBadge";
import { SessionGate } from "./SessionGate";

afterEach(() => {
  vi.unstubAllGlobals();
});

const UNAUTHORIZED = { error: "unauthorized", message: "log in first" };

/** Stands in for the app: who is logged in, where, and one API call to make. */
function FakeApp(): ReactNode {
  const { user, role } = useSession();
  const { pathname } = useLocation();
  const [bus, setBus] = useState<string | null>(null);
  return (
    <div>
      <p>
        App for {user} ({role}) at {pathname}
      </p>
      <button
        type="button"
        onClick={() =>
          void call(api.GET("/api/bus")).then(
            (b) => setBus(b.state),
            () => undefined,
          )
        }
      >
        Read bus
      </button>
      {bus && <p>Bus {bus}</p>}
      <SessionBadge />
    </div>
  );
}

function renderGate(url = "/nodes/1/od"): void {
  render(
    <MemoryRouter initialEntries={[url]}>
      <SessionGate>
        <FakeApp />
      </SessionGate>
    </MemoryRouter>,
  );
}

describe("the login session", () => {
  it("asks for a token on 401, says a wrong one is wrong, then loads the app on the same page", async () => {
    let loggedIn = false;
    const fetch = stubFetch({
      "GET /api/session": () => (loggedIn ? sessionAs("engineer", "eng") : json(UNAUTHORIZED, 401)),
      "POST /api/login": async (request: Request) => {
        const { token } = (await request.json()) as { token: string };
        if (token !== "right") return json({ error: "unauthorized", message: "bad token" }, 401);
        loggedIn = true;
        return sessionAs("engineer", "eng");
      },
    });
    renderGate();

    const token = await screen.findByLabelText("Access token");
    expect(token.getAttribute("type")).toBe("password");
    await userEvent.type(token, "wrong");
    await userEvent.click(screen.getByRole("button", { name: "Log in" }));
    expect((await screen.findByRole("alert")).textContent).toContain("Wrong token");

    await userEvent.clear(token);
    await userEvent.type(token, "right");
    await userEvent.click(screen.getByRole("button", { name: "Log in" }));
    expect(await screen.findByText("App for eng (engineer) at /nodes/1/od")).toBeTruthy();
    expect(screen.getByTestId("session-user").textContent).toBe("eng · engineer");
    const login = fetch.calls.filter((c) => c.path === "/api/login").at(-1);
    expect(login?.body).toBe('{"token":"right"}');
  });

  it("shows the wait when the server rate-limits logins", async () => {
    stubFetch({
      "GET /api/session": json(UNAUTHORIZED, 401),
      "POST /api/login": json(
        { error: "rate_limited", message: "too many attempts", retry_after_s: 42 },
        429,
      ),
    });
    renderGate();
    await userEvent.type(await screen.findByLabelText("Access token"), "guess");
    await userEvent.click(screen.getByRole("button", { name: "Log in" }));
    expect((await screen.findByRole("alert")).textContent).toBe(
      "Too many login attempts. Wait 42 s before trying again.",
    );
  });

  it("goes back to the login screen when any request answers 401, and logs out", async () => {
    let expired = false;
    stubFetch({
      "GET /api/session": () => (expired ? json(UNAUTHORIZED, 401) : sessionAs("operator", "op")),
      "GET /api/bus": () => (expired ? json(UNAUTHORIZED, 401) : { state: "connected" }),
      "POST /api/logout": () => new Response(null, { status: 204 }),
    });
    renderGate("/drive");
    await userEvent.click(await screen.findByRole("button", { name: "Read bus" }));
    expect(await screen.findByText("Bus connected")).toBeTruthy();

    expired = true;
    await userEvent.click(screen.getByRole("button", { name: "Read bus" }));
    expect(await screen.findByLabelText("Access token")).toBeTruthy();
    expect(screen.queryByText(/App for/)).toBeNull();
  });

  it("logs out from the sidebar badge", async () => {
    const fetch = stubFetch({
      "GET /api/session": sessionAs("viewer", "view"),
      "POST /api/logout": () => new Response(null, { status: 204 }),
    });
    renderGate("/");
    await userEvent.click(await screen.findByRole("button", { name: "Log out" }));
    expect(await screen.findByLabelText("Access token")).toBeTruthy();
    expect(fetch.calls.some((c) => c.method === "POST" && c.path === "/api/logout")).toBe(true);
  });

  it("shows no badge on a server without logins", async () => {
    stubFetch({
      "GET /api/session": {
        user: "local",
        role: "engineer",
        auth_required: false,
        may: { operate: true, configure: true },
      },
    });
    renderGate("/");
    expect(await screen.findByText("App for local (engineer) at /")).toBeTruthy();
    expect(screen.queryByRole("button", { name: "Log out" })).toBeNull();
  });
});

describe("permit", () => {
  it("explains what each role lacks", () => {
    expect(permit(sessionAs("viewer"), "operate").because("jog the drive")).toBe(
      "Viewer role: read only — log in as an operator or engineer to jog the drive",
    );
    expect(permit(sessionAs("operator"), "configure").because("write parameters")).toBe(
      "Operator role: runs the drives but does not change their configuration — log in as an engineer to write parameters",
    );
    const engineer = permit(sessionAs("engineer"), "configure");
    expect(engineer.gate("write parameters", { disabled: false, title: "Write" })).toEqual({
      disabled: false,
      title: "Write",
    });
  });
});
