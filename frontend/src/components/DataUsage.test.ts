import { describe, expect, it } from "vitest";

import { usageWords, type Usage } from "./DataUsage";

const MiB = 1024 * 1024;
const GiB = 1024 * MiB;

const USAGE: Usage = {
  total_bytes: 1.5 * GiB,
  free_bytes: 40 * GiB,
  logs_bytes: 300 * MiB,
  logs_keep_bytes: 2 * GiB,
  captures_bytes: 1.1 * GiB,
  captures_keep_bytes: 8 * GiB,
  recordings_bytes: 20 * MiB,
  min_free_bytes: 512 * MiB,
};

describe("usageWords", () => {
  it.each([
    [
      undefined,
      USAGE,
      "Data directory: 1.5 GiB (decoded logs 300.0 MiB, captures 1.1 GiB, recordings 20.0 MiB) · 40.0 GiB free on the disk",
      false,
    ],
    [
      "captures" as const,
      USAGE,
      "Captures take 1.1 GiB of the 8.0 GiB kept; beyond that the oldest are deleted · 40.0 GiB free on the disk",
      false,
    ],
    [
      "logs" as const,
      { ...USAGE, logs_bytes: 1.9 * GiB },
      "Decoded logs take 1.9 GiB of the 2.0 GiB kept; beyond that the oldest are deleted · 40.0 GiB free on the disk",
      true,
    ],
    [
      "captures" as const,
      { ...USAGE, free_bytes: 700 * MiB },
      "Captures take 1.1 GiB of the 8.0 GiB kept; beyond that the oldest are deleted · 700.0 MiB free on the disk; below 512.0 MiB free, captures end to leave room for the audit log",
      true,
    ],
  ])("%s", (kind, usage, text, warn) => {
    expect(usageWords(usage, kind)).toEqual({ text, warn });
  });
});
