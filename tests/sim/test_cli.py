"""`servodesk-sim` argument handling: what a user sees for good and bad command lines."""

from __future__ import annotations

import argparse
import socket

import pytest

from servodesk_sim.cli import connect_hint, main, parse_node, parse_serve
from servodesk_sim.frames import Frame
from servodesk_sim.runner import SimNode

PROFILES = ("mdi-s1c", "kinco", "cia402")


class QuietNode:
    def __init__(self, node_id: int) -> None:
        self._node_id = node_id

    @property
    def node_id(self) -> int:
        return self._node_id

    def boot(self, now: float) -> list[Frame]:
        return []

    def on_frame(self, f: Frame, now: float) -> list[Frame]:
        return []

    def poll(self, now: float) -> list[Frame]:
        return []


def quiet(node_id: int, _profile: str) -> SimNode:
    return QuietNode(node_id)


def run_expecting_exit(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """Run main() to an argparse exit; returns (status, stderr)."""
    with pytest.raises(SystemExit) as exc:
        main(argv, make_node=quiet, profile_names=PROFILES)
    code = exc.value.code
    return (code if isinstance(code, int) else 1), capsys.readouterr().err


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("4:mdi-s1c", (4, "mdi-s1c")),
        ("1:kinco", (1, "kinco")),
        ("127:cia402", (127, "cia402")),
        ("0x7F:cia402", (127, "cia402")),
    ],
)
def test_parse_node(text: str, expected: tuple[int, str]) -> None:
    assert parse_node(text) == expected


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("4", "is not ID:PROFILE"),
        (":kinco", "is not ID:PROFILE"),
        ("4:", "is not ID:PROFILE"),
        ("four:kinco", "is not a number"),
        ("0:kinco", "outside 1–127"),
        ("128:kinco", "outside 1–127"),
    ],
)
def test_parse_node_rejects(text: str, message: str) -> None:
    with pytest.raises(argparse.ArgumentTypeError, match=message):
        parse_node(text)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("127.0.0.1:29536", ("127.0.0.1", 29536)),
        ("localhost:0", ("localhost", 0)),
    ],
)
def test_parse_serve(text: str, expected: tuple[str, int]) -> None:
    assert parse_serve(text) == expected


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("29536", "is not HOST:PORT"),
        ("127.0.0.1:http", "is not a number"),
        ("127.0.0.1:70000", "outside 0–65535"),
        ("0.0.0.0:29536", "refusing to serve on 0.0.0.0"),
        ("192.168.0.5:29536", "only loopback"),
        ("[::1]:29536", "connects over IPv4 only"),
    ],
)
def test_parse_serve_rejects(text: str, message: str) -> None:
    with pytest.raises(argparse.ArgumentTypeError, match=message):
        parse_serve(text)


def test_help_lists_the_bus_flags_of_python_can_and_ours(
    capsys: pytest.CaptureFixture[str],
) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    for flag in ("--interface", "--channel", "--bitrate", "--bus-kwargs", "--node", "--serve"):
        assert flag in out
    assert "servodesk-sim" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        ([], "the following arguments are required: --node"),
        (["--node", "4"], "argument --node: '4' is not ID:PROFILE"),
        (["--node", "200:kinco"], "node id 200 is outside 1–127"),
        (["--node", "4:kinco", "--node", "4:cia402"], "node id 4 is given twice"),
        (
            ["--node", "4:servo9000"],
            "unknown profile 'servo9000' for node 4 (known: cia402, kinco, mdi-s1c)",
        ),
        (["--node", "4:kinco", "--serve", "0.0.0.0:29536"], "refusing to serve on 0.0.0.0"),
        (["--node", "4:kinco", "-i", "no-such-interface"], "argument -i/--interface"),
        (["--node", "4:kinco", "-i", "udp_multicast"], "sends the drives' frames to the local"),
    ],
)
def test_bad_command_lines_exit_2_with_a_clear_message(
    argv: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code, err = run_expecting_exit(argv, capsys)
    assert code == 2
    assert message in err
    assert "usage: servodesk-sim" in err


def test_a_drive_that_cannot_be_built_is_a_usage_error(
    capsys: pytest.CaptureFixture[str],
) -> None:
    def refuse(_node_id: int, _profile: str) -> SimNode:
        raise ValueError("bitrate 123 is not supported by kinco")

    with pytest.raises(SystemExit) as exc:
        main(["--node", "4:kinco", "-b", "123"], make_node=refuse, profile_names=PROFILES)
    assert exc.value.code == 2
    assert "bitrate 123 is not supported by kinco" in capsys.readouterr().err


def test_a_bus_that_cannot_open_is_reported(capsys: pytest.CaptureFixture[str]) -> None:
    # socketcan needs kernel CAN support and an existing interface; neither is here
    code = main(
        ["--node", "4:kinco", "-i", "socketcan", "-c", "servodesk-missing0"],
        make_node=quiet,
        profile_names=PROFILES,
    )
    assert code == 1
    assert "cannot open the bus" in capsys.readouterr().err


def test_connect_hint_is_a_working_python_can_command_line() -> None:
    hint = connect_hint("127.0.0.1", 29536)
    assert hint.splitlines()[0] == "listening on 127.0.0.1:29536 (socketcand, channel can0)"
    assert (
        "python -m can.logger -i socketcand -c can0 --bus-kwargs host=127.0.0.1 port=29536" in hint
    )
    assert 'can.Bus(interface="socketcand", host="127.0.0.1", port=29536, channel="can0")' in hint


def test_a_port_in_use_is_reported(capsys: pytest.CaptureFixture[str]) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        code = main(
            ["--node", "4:kinco", "--serve", f"127.0.0.1:{port}"],
            make_node=quiet,
            profile_names=PROFILES,
        )
    assert code == 1
    assert f"cannot serve on 127.0.0.1:{port}" in capsys.readouterr().err
