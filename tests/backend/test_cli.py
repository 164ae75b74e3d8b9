"""`servodesk` field commands against the built-in simulated drives (`--sim`)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from pydantic import SecretStr

from servodesk.cli import build_parser, main
from servodesk.cli_serve import serve_refusal
from servodesk.settings import Settings

SHARED_EDS = Path(__file__).resolve().parents[2] / ".." / "shared" / "eds"


def test_scan_lists_the_simulated_drives(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["scan", "--sim"]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert lines[0].split() == ["node", "state", "profile", "name"]
    assert lines[1].split()[:3] == ["1", "pre-operational", "mdi-s1c"]
    assert "DVS_CANOPEN" in lines[1]
    assert [line.split()[0] for line in lines[1:]] == ["1", "2", "3"]


def test_read_and_write(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["read", "1", "1008", "0", "--sim"]) == 0
    assert capsys.readouterr().out.strip() == "DVS_CANOPEN"
    assert main(["write", "1", "6081", "0", "0x2710", "--sim"]) == 0
    assert "10000" in capsys.readouterr().out


def test_write_abort_is_reported_with_its_code(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["write", "1", "6041", "0", "6", "--sim"]) == 1
    err = capsys.readouterr().err
    assert "0x06010002" in err
    assert "Attempt to write a read-only object" in err


def test_dump_writes_a_dcf_that_loads_again(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    assert main(["dump", "3", "--sim"]) == 0
    dcf = tmp_path / "node3.dcf"
    dcf.write_text(capsys.readouterr().out)
    assert "[DeviceComissioning]" in dcf.read_text()
    assert main(["eds-check", str(dcf)]) == 0
    assert "DCF" in capsys.readouterr().out


def test_eds_check_reports_problems_and_fails_only_on_unusable_files(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    assert main(["eds-check", str(SHARED_EDS / "Demaclenko_emecdrv5_rev09.eds")]) == 0
    out = capsys.readouterr().out
    assert "byte-swapped" in out
    junk = tmp_path / "junk.eds"
    junk.write_bytes(b"\x00\x01\x02 nothing here")
    assert main(["eds-check", str(junk)]) == 1


def test_serve_refuses_non_loopback_addresses(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["serve", "--sim", "--bind", "0.0.0.0"]) == 2  # the refusal is the test
    assert "without access tokens" in capsys.readouterr().err


def test_every_command_takes_python_can_bus_flags() -> None:
    args = build_parser().parse_args(
        ["read", "1", "1008", "0", "-i", "socketcand", "-c", "can0", "--bus-kwargs", "port=1"]
    )
    assert (args.interface, args.channel, args.bus_kwargs) == ("socketcand", "can0", {"port": 1})


def one_line_error(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert 1 <= len(lines) <= 2, err
    return err


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["read", "1", "zz", "0", "--sim"], "index 'zz' is not hexadecimal"),
        (["read", "1", "10000", "0", "--sim"], "index '10000' is outside 0–FFFF"),
        (["read", "1", "1008", "100", "--sim"], "sub-index '100' is outside 0–FF"),
        (["read", "0", "1008", "0", "--sim"], "node id 0 is outside 1–127"),
        (["write", "x", "1008", "0", "1", "--sim"], "node id 'x' is not a number"),
        (["dump", "128", "--sim"], "node id 128 is outside 1–127"),
    ],
)
def test_bad_arguments_are_one_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], says: str
) -> None:
    with pytest.raises(SystemExit) as exited:
        main(argv)
    assert exited.value.code == 2
    assert says in one_line_error(capsys)


@pytest.fixture
def no_can_config(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """A machine where python-can finds no configuration (no file, no environment)."""
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.chdir(tmp_path)
    for name in ("CAN_INTERFACE", "CAN_CHANNEL", "CAN_BITRATE", "CAN_CONFIG"):
        monkeypatch.delenv(name, raising=False)


@pytest.mark.usefixtures("no_can_config")
@pytest.mark.parametrize("argv", [["scan"], ["read", "1", "1008", "0"], ["dump", "1"]])
def test_no_interface_says_what_to_pass(
    capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    assert main(argv) == 1
    err = one_line_error(capsys)
    assert "no CAN interface given: pass -i/--interface" in err
    assert "--sim" in err


def test_a_bus_that_cannot_open_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["scan", "-i", "socketcan", "-c", "nocan9"]) == 1
    assert "servodesk: could not open the CAN bus:" in one_line_error(capsys)


def test_an_absent_node_is_one_message(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["read", "5", "1008", "0", "--sim"]) == 1
    err = one_line_error(capsys)
    assert err == "servodesk: node 5: no answer to identify node 5 (read 1000h)\n"


def test_an_abort_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["write", "1", "6041", "0", "6", "--sim"]) == 1
    assert "0x06010002" in one_line_error(capsys)


def test_debug_shows_the_traceback(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--debug", "read", "5", "1008", "0", "--sim"]) == 1
    err = capsys.readouterr().err
    assert "Traceback" in err
    assert err.strip().endswith("servodesk: node 5: no answer to identify node 5 (read 1000h)")


def test_serve_checks_tokens_and_tls_before_starting(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    tokens = tmp_path / "tokens"
    tokens.write_text("alice:engineer=alice-token-0123\nbob:admin=bob-token-0123456\n")
    assert main(["serve", "--sim", "--tokens-file", str(tokens)]) == 2
    assert f"{tokens}:2: unknown role 'admin'" in capsys.readouterr().err
    assert main(["serve", "--sim", "--tls-cert", str(tokens)]) == 2
    assert "needs both --tls-cert and --tls-key" in capsys.readouterr().err
    missing = tmp_path / "missing.pem"
    assert main(["serve", "--sim", "--tls-cert", str(missing), "--tls-key", str(missing)]) == 2
    assert "is not a readable file" in capsys.readouterr().err


def test_serving_beyond_loopback_with_tokens_is_allowed() -> None:
    with_tokens = Settings(bind="0.0.0.0", tokens=SecretStr("engineer=eng-token-0123456"))
    assert serve_refusal(with_tokens) is None
    refused = serve_refusal(Settings(bind="10.1.2.3"))
    assert refused is not None
    assert "SERVODESK_TOKENS" in refused


HEAVY = ("can", "canopen", "asammdf", "pandas", "uvicorn", "fastapi")
PROBE = """
import contextlib, io, sys
from servodesk.cli import main
with contextlib.suppress(SystemExit), contextlib.redirect_stdout(io.StringIO()):
    main(sys.argv[1:])
print(",".join(m for m in {heavy!r} if m in sys.modules))
"""


@pytest.mark.parametrize(
    "argv",
    [["--help"], ["eds-check", str(SHARED_EDS / "Sevcon_sevcon_gen4_simstub.eds")]],
)
def test_a_command_imports_what_it_uses(argv: list[str]) -> None:
    """`--help` and `eds-check` never load python-can (with asammdf and pandas: a second) or
    the web server: bench/cli_startup.py times them."""
    probe = subprocess.run(
        [sys.executable, "-c", PROBE.format(heavy=HEAVY), *argv],
        capture_output=True,
        text=True,
        check=True,
    )
    assert probe.stdout.strip() == ""


def test_serve_help_still_lists_python_cans_bus_flags(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["serve", "--help"])
    out = capsys.readouterr().out
    assert "--interface" in out
    assert "--bus-kwargs" in out
