// Canned answers for the Object dictionary page tests: node 3's CiA 402 profile dictionary.
import type { OdTree } from "../../api/types";

const base = {
  pdo_mappable: false,
  default: null,
  low: null,
  high: null,
  unit: "",
  description: "",
};

export const TREE: OdTree = {
  source: "profile",
  filename: "cia402/drive.eds",
  warnings: [],
  objects: [
    {
      index: 0x1000,
      index_hex: "1000",
      name: "Device type",
      object_type: "var",
      subs: [
        {
          ...base,
          index: 0x1000,
          subindex: 0,
          name: "Device type",
          data_type: 7,
          data_type_name: "UNSIGNED32",
          access: "ro",
        },
      ],
    },
    {
      index: 0x1018,
      index_hex: "1018",
      name: "Identity object",
      object_type: "record",
      subs: [
        {
          ...base,
          index: 0x1018,
          subindex: 0,
          name: "Highest sub-index supported",
          data_type: 5,
          data_type_name: "UNSIGNED8",
          access: "const",
        },
        {
          ...base,
          index: 0x1018,
          subindex: 1,
          name: "Vendor-ID",
          data_type: 7,
          data_type_name: "UNSIGNED32",
          access: "ro",
        },
        {
          ...base,
          index: 0x1018,
          subindex: 2,
          name: "Product code",
          data_type: 7,
          data_type_name: "UNSIGNED32",
          access: "ro",
        },
      ],
    },
    {
      index: 0x6060,
      index_hex: "6060",
      name: "Modes of operation",
      object_type: "var",
      subs: [
        {
          ...base,
          index: 0x6060,
          subindex: 0,
          name: "Modes of operation",
          data_type: 2,
          data_type_name: "INTEGER8",
          access: "rw",
        },
      ],
    },
  ],
};

const UPLOAD_JOB = { id: "j1", kind: "upload-all" as const, node: 3, total: 2, error: null };

/** Node 3's upload-all job: one value at the start, then done with one object not readable. */
export const UPLOAD_ALL = {
  "POST /api/nodes/3/upload-all": {
    ...UPLOAD_JOB,
    state: "running",
    done: 1,
    elapsed_s: 0.1,
    results_from: 0,
    results: [
      { index: 0x1000, subindex: 0, name: "Device type", value: 1, text: "0x00000001 (1)" },
    ],
  },
  "GET /api/jobs/j1": {
    ...UPLOAD_JOB,
    state: "done",
    done: 2,
    elapsed_s: 0.3,
    results_from: 1,
    results: [
      {
        index: 0x6060,
        subindex: 0,
        name: "Modes of operation",
        abort_code: "0x06020000",
        message: "Object does not exist in the object dictionary",
      },
    ],
  },
};

/** Node 3's 1000h read by SDO. */
export const DEVICE_TYPE = {
  node: 3,
  index: 0x1000,
  subindex: 0,
  name: "Device type",
  data_type_name: "UNSIGNED32",
  value: 131474,
  raw_hex: "92 01 02 00",
  text: "0x00020192 (131474)",
};
