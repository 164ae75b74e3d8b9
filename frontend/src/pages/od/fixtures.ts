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
