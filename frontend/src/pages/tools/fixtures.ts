// Canned answer for the Tools page tests: POST /api/od/check of drive.eds, one error and one
// note among its findings.
import type { OdCheckResult } from "../../api/types";

export const CHECKED: OdCheckResult = {
  filename: "drive.eds",
  format: "eds",
  objects: 227,
  device: {
    vendor_name: "Nanotec",
    vendor_number: 0x26c,
    product_name: "C5-E",
    product_number: 0x11,
  },
  warnings: [
    {
      file: "drive.eds",
      line: 121,
      section: "1018sub4",
      key: "DefaultValue",
      code: "empty-default",
      message: "DefaultValue is empty",
      severity: "info",
    },
    {
      file: "drive.eds",
      line: 40,
      section: "1000",
      key: "DataType",
      code: "bad-type",
      message: "Unknown data type",
      severity: "error",
    },
  ],
};
