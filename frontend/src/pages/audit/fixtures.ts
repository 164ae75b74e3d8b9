// Canned audit entries for the Audit page tests: a write of 6081h:00 (entry 12), a refused write
// of 1000h:00 (entry 11) and the undo of entry 12 (entry 13).
import type { AuditEntry } from "./types";

/** Entry `id`: engineer wrote 6081h:00 from 1000 to 2000, unless `fields` say otherwise. */
export const entry = (id: number, fields: Partial<AuditEntry> = {}): AuditEntry => ({
  id,
  time: 1_750_000_000 + id,
  finished: 1_750_000_000 + id,
  user: "engineer",
  role: "engineer",
  client: "127.0.0.1 · Firefox",
  node: 1,
  action: "sdo-write",
  what: "write node 1 6081h:00 Profile velocity = 2000",
  index: 0x6081,
  subindex: 0,
  old: 1000,
  new: 2000,
  result: "ok",
  abort_code: null,
  error: null,
  message: null,
  undo_of: null,
  undone_by: null,
  undoable: true,
  ...fields,
});

export const WRITE = entry(12);
export const FAILED = entry(11, {
  index: 0x1000,
  what: "write node 1 1000h:00",
  old: 0x20192,
  new: 5,
  result: "failed",
  abort_code: "0x06010002",
  message: "Attempt to write a read-only object",
  undoable: false,
});
export const UNDO = entry(13, {
  action: "undo",
  what: "undo entry 12: write node 1 6081h:00 = 1000 (back from 2000)",
  old: 2000,
  new: 1000,
  undo_of: 12,
  undoable: false,
});
