"""Large valid EDS files made on the fly (the benchmark and the upload tests use them)."""

from __future__ import annotations

import servodesk_data


def make_eds(size: int) -> bytes:
    """The CiA 402 drive's EDS plus records of 8 UNSIGNED32 entries until `size` bytes."""
    head = servodesk_data.eds_path("cia402").read_text(encoding="utf-8")
    parts = [head, "\n"]
    total = len(head)
    index = 0x3000
    while total < size - 2048 and index <= 0x5FEF:
        record = [
            f"[{index:04X}]\nParameterName=Generated record {index:04X}\nObjectType=0x9\n"
            "SubNumber=9\n\n",
            f"[{index:04X}sub0]\nParameterName=Highest sub-index supported\nObjectType=0x7\n"
            "DataType=0x0005\nAccessType=ro\nDefaultValue=8\nPDOMapping=0\n\n",
        ]
        for sub in range(1, 9):
            record.append(
                f"[{index:04X}sub{sub}]\nParameterName=Generated value {sub} of {index:04X}\n"
                f"ObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x{sub * 1000:08X}"
                "\nLowLimit=0\nHighLimit=0x7FFFFFFF\nPDOMapping=1\n\n"
            )
        text = "".join(record)
        parts.append(text)
        total += len(text)
        index += 1
    return "".join(parts).encode()
