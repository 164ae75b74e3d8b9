// Canned answers for the Logs page tests: a decoded bus.log (700 events, the first 500 sent),
// the recording at rest and two decoded logs kept on the server.
import type { KeptLog, LogEvent, RecordingInfo } from "./types";

/** Decoded event `seq`, an SDO of node 1 unless told otherwise. */
export const event = (seq: number, kind = "sdo", text = `event ${seq}`): LogEvent => ({
  seq,
  time: seq / 10,
  frame: seq + 1,
  kind,
  node: 1,
  text,
  index: null,
  subindex: null,
  code: null,
  data: null,
  polling: false,
});

export const decoded = {
  id: "abc123",
  name: "bus.log",
  summary: [
    "1,200 frames over 2.500 s (+0.000 s – +2.500 s) from node 1 (MDi-S1-C).",
    "Bus load at 500 kbit/s: peak 3.1 % in the second from +0.000 s, mean 1.2 %.",
    "1 EMCY(s), 0 SDO abort(s), 0 heartbeat loss(es).",
    "+1.200 s node 1 EMCY: alarm 4 位置超差 Following error",
  ],
  stats: {
    frames: 1200,
    duration_s: 2.5,
    nodes: [1],
    counts: { emcy: 1, sdo: 600 },
    bitrate: 500000,
    bus_load_peak_percent: 3.1,
    bus_load_mean_percent: 1.2,
    events: 700,
    error_frames: 0,
  },
  events: Array.from({ length: 500 }, (_, i) => event(i)),
  next: 500,
};

/** GET /api/recording when nothing is being recorded. */
export const notRecording: RecordingInfo = {
  active: false,
  format: null,
  file: null,
  since: null,
  frames: 0,
  dropped: 0,
};

/** GET /api/logs: bus.log (the decoded one above) and an older old.blf. */
export const kept: KeptLog[] = [
  { id: "abc123", name: "bus.log", size_bytes: 3 * 1024 * 1024, created: 1795757000 },
  { id: "def456", name: "old.blf", size_bytes: 2048, created: 1795750000 },
];
