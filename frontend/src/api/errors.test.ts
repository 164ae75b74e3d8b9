import { afterEach, describe, expect, it, vi } from "vitest";

import { json, stubFetch } from "../test/fetchStub";
import { api, call } from "./client";
import { ApiError, asApiError, formatAbortCode, toApiError } from "./errors";

afterEach(() => {
  vi.unstubAllGlobals();
});

describe("ApiError", () => {
  it("shows an SDO abort as code beside its meaning", () => {
    const error = toApiError(409, {
      error: "sdo_abort",
      message: "Attempt to write a read-only object",
      abort_code: "0x06010002",
      node: 1,
    });
    expect(error.kind).toBe("sdo_abort");
    expect(error.status).toBe(409);
    expect(error.abortCode).toBe("0x06010002");
    expect(error.describe()).toBe("0x06010002 — Attempt to write a read-only object");
  });

  it("shows other kinds as their message only", () => {
    const error = toApiError(503, { error: "bus_not_connected", message: "No CAN bus connected" });
    expect(error.kind).toBe("bus_not_connected");
    expect(error.describe()).toBe("No CAN bus connected");
  });

  it("reads FastAPI's validation body", () => {
    const error = toApiError(422, {
      detail: [{ loc: ["body", "value"], msg: "Field required", type: "missing" }],
    });
    expect(error.kind).toBe("validation_error");
    expect(error.describe()).toBe("body.value: Field required");
  });

  it("falls back to the status for bodies it does not know", () => {
    expect(toApiError(500, null, "Internal Server Error").describe()).toBe(
      "HTTP 500 Internal Server Error",
    );
    expect(toApiError(502, "Bad gateway\n").describe()).toBe("Bad gateway");
    expect(toApiError(418, { error: "teapot", message: "short and stout" }).kind).toBe("error");
  });

  it.each([
    ["0x6010002", "0x06010002"],
    ["08000022", "0x08000022"],
    [0x05040000, "0x05040000"],
  ])("formats abort code %s as %s", (input, expected) => {
    expect(formatAbortCode(input)).toBe(expected);
  });

  it("turns a failed fetch into a network error", () => {
    const error = asApiError(new TypeError("Failed to fetch"));
    expect(error).toBeInstanceOf(ApiError);
    expect(error.kind).toBe("network");
    expect(error.describe()).toContain("Failed to fetch");
  });
});

describe("call", () => {
  it("returns the data of a successful request", async () => {
    stubFetch({ "GET /api/nodes/2/heartbeat": { producer_ms: 100 } });
    const result = await call(
      api.GET("/api/nodes/{node}/heartbeat", { params: { path: { node: 2 } } }),
    );
    expect(result.producer_ms).toBe(100);
  });

  it("throws the backend's error as ApiError", async () => {
    stubFetch({
      "GET /api/nodes/5/heartbeat": json(
        { error: "node_not_found", message: "node 5 is not known", node: 5 },
        404,
      ),
    });
    const promise = call(api.GET("/api/nodes/{node}/heartbeat", { params: { path: { node: 5 } } }));
    await expect(promise).rejects.toMatchObject({
      kind: "node_not_found",
      status: 404,
      message: "node 5 is not known",
    });
  });
});
