"""The one-line warning format a CLI prints."""

from __future__ import annotations

import pytest

from servodesk.od import LintWarning, load_od_bytes
from servodesk.od.lint import format_warning, lint_report


@pytest.mark.parametrize(
    ("warning", "text"),
    [
        (
            LintWarning(
                "a.eds", 12, "1018", "SubNumber", "subnumber-mismatch", "Too few.", "warning"
            ),
            "a.eds:12 [1018] SubNumber: Too few. (warning subnumber-mismatch)",
        ),
        (
            LintWarning("a.eds", 3, None, None, "encoding", "Read as GBK.", "warning"),
            "a.eds:3: Read as GBK. (warning encoding)",
        ),
        (
            LintWarning("a.xdd", None, "2000", None, "xml", "Odd.", "info"),
            "a.xdd [2000]: Odd. (info xml)",
        ),
    ],
)
def test_format_warning(warning: LintWarning, text: str) -> None:
    assert format_warning(warning) == text


def test_report_is_sorted_by_line() -> None:
    data = (
        b"[2000]\nParameterName=X\nDataType=0x0006\nAccessType=rw\nDefaultValue=zz\n"
        b"[1000]\nParameterName=Device type\nDataType=0x0007\nAccessType=ro\n"
        b"[DeviceInfo]\nVendorNumber=\n"
    )
    model = load_od_bytes(data, "u.eds")
    lines = lint_report(model).splitlines()
    numbers = [int(line.split(":")[1].split(" ")[0]) for line in lines]
    assert numbers == sorted(numbers)
    assert len(lines) == len(model.warnings) == 2
