"""All settings in one place: environment variables `SERVODESK_*`, then CLI flags override."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from platformdirs import user_data_path
from pydantic import Field, SecretStr
from pydantic_settings import BaseSettings, SettingsConfigDict


def default_data_dir() -> Path:
    """The user's data directory for ServoDesk: `~/.local/share/servodesk` on Linux (or under
    `$XDG_DATA_HOME`), `%LOCALAPPDATA%\\servodesk` on Windows, `~/Library/Application
    Support/servodesk` on macOS. Where an earlier version's `~/.local/share/servodesk` holds
    data and the platform's directory does not exist yet, that one is kept."""
    chosen = user_data_path("servodesk", appauthor=False)
    earlier = Path.home() / ".local" / "share" / "servodesk"
    if chosen != earlier and not chosen.exists() and earlier.is_dir():
        return earlier
    return chosen


class Settings(BaseSettings):
    model_config = SettingsConfigDict(env_prefix="SERVODESK_", extra="ignore")

    # Where the web app listens. Beyond loopback needs access tokens (docs/security.md).
    bind: str = "127.0.0.1"
    port: int = 8000
    # Access tokens per role: "engineer=…,operator=…,viewer=…" (or "user:role=…"), and/or a
    # file with one such entry per line. Once any is configured, every request needs one.
    tokens: SecretStr | None = None
    tokens_file: Path | None = None
    # Host names (besides loopback and the bound address) the app may be reached by,
    # comma-separated: checked against Host and Origin headers (DNS rebinding).
    allowed_hosts: str = ""
    # Reverse proxies whose X-Forwarded-For / X-Forwarded-Proto are believed, comma-separated
    # addresses or networks ("*": any), as uvicorn's --forwarded-allow-ips. None by default: a
    # header any local program can send must not choose the client address that the audit log
    # records and the login limit counts.
    forwarded_allow_ips: str = ""
    # Wrong tokens (logins and bearer tokens) one client address may send per minute, and all
    # addresses together, before they wait (429); a right token is refused too meanwhile.
    token_failures_per_client: int = Field(default=5, ge=1, le=100_000)
    token_failures_overall: int = Field(default=30, ge=1, le=1_000_000)
    # HTTPS with uvicorn's own TLS: both files, PEM
    tls_cert: Path | None = None
    tls_key: Path | None = None

    # CAN bus. None values fall back to python-can's own config file and environment.
    interface: str | None = None
    channel: str | None = None
    bitrate: int | None = None
    # python-can keyword arguments as parsed by its CLI (`port=29536` arrives as an int)
    bus_options: dict[str, Any] = Field(default_factory=dict)
    simulated: bool = False  # start the three built-in simulated drives (nodes 1, 2, 3)

    # Timeouts and timing (seconds unless the name says otherwise)
    sdo_timeout: float = 0.5
    scan_timeout: float = 0.05
    heartbeat_lost_factor: float = 1.5  # a node is lost after factor × its heartbeat period
    default_heartbeat_timeout: float = 3.0  # when its period is unknown
    reconnect_initial_delay: float = 0.5
    reconnect_max_delay: float = 5.0
    boot_wait: float = 3.0  # waiting for a boot-up after a reset
    # Find the nodes by themselves after a (re)connect and when an unknown node boots; the CLI
    # turns this off because each of its commands says what to look for.
    auto_scan: bool = True

    # Motion safety (DESIGN: Motion safety). The tool produces its own heartbeat on this node id
    # while it controls a drive, and sets the drive's heartbeat consumer (1016h) to it: if the
    # tool dies, the drive stops by itself after `heartbeat_consumer_ms`.
    tool_node_id: int = Field(default=127, ge=1, le=127)
    heartbeat_consumer_ms: int = Field(default=300, ge=50, le=5000)
    tool_heartbeat_ms: int = Field(default=100, ge=10, le=1000)  # well inside the consumer time
    # The heartbeat is withheld once the event loop has not run for this long (the loop stops
    # jogs; a loop that cannot is no controller): a hung server's drives then stop by themselves
    # within this + one heartbeat period + the consumer time (docs/architecture.md)
    tool_heartbeat_liveness_ms: int = Field(default=500, ge=50, le=5000)
    jog_keepalive_max_ms: int = 500  # hold-to-run: the longest keep-alive interval a jog may ask
    # A live WebSocket that sends nothing for this long is closed as gone (pages ping every
    # 10 s): a page killed without a close frame releases its drives within this, not after
    # TCP gives up
    live_silence_s: float = Field(default=25.0, gt=0)
    # A jog's stop decelerates at least this hard (rpm/s), whatever ramp the client asked for,
    # and at the drive's quick stop deceleration 6085h where that is steeper: a stop on lost
    # control must not take minutes because a client chose a slow ramp.
    jog_stop_deceleration_rpm_s: float = Field(default=1000.0, gt=0)
    jog_rest_rpm: float = Field(default=5.0, gt=0)  # below this the axis counts as at rest
    # ServoDesk's own speed cap of a torque jog (rpm) where the request names none; the jog
    # is stopped when the axis passes it (no load: a small torque runs up to the drive's max)
    jog_pt_speed_cap_rpm: float = Field(default=300.0, gt=0)
    jog_watch_interval: float = Field(default=0.03, gt=0)  # s: velocity reads while jogging

    # Motion (CiA 402). Timeouts in s; `motion_transition_timeouts` overrides the transition
    # time per profile name ("mdi-s1c": 0.8) for drives that need longer to power their stage.
    motion_transition_timeout: float = 0.5  # one state machine transition (enable, reset…)
    motion_transition_timeouts: dict[str, float] = Field(default_factory=dict)
    motion_setpoint_timeout: float = 0.5  # PP set-point acknowledge (statusword bit 12)
    motion_move_timeout: float = 60.0  # a queued set-point that never reaches its target
    motion_homing_timeout: float = 70.0  # the drives themselves give up after 60 s
    motion_poll_interval: float = 0.02  # reading the statusword while waiting
    # The pages' drive state (GET …/drive, the live channel): one reading per period shared by
    # every client, the objects no TPDO carries read by SDO at most `drive_poll_sdo_budget` at
    # a time (the worker queue a jog's writes wait in stays short)
    drive_poll_period: float = Field(default=0.1, gt=0)
    drive_poll_sdo_budget: int = Field(default=2, ge=1)
    motion_default_acceleration_rpm_s: float = 1000.0  # moves and jogs that name none
    # Caps on the limits each node starts with (its overspeed object and 6072h otherwise)
    motion_max_velocity_rpm: float | None = None
    motion_max_torque_pct: float | None = None
    motion_ip_max_duration: float = 30.0  # the longest interpolated stream (s)

    # Timeline and fault history (SQLite in data_dir), pruned by the writer beyond these bounds
    events_max_rows: int = Field(default=200_000, ge=1000)
    events_max_days: float = Field(default=30.0, gt=0)
    faults_max_rows: int = Field(default=50_000, ge=1000)
    # Offline log analysis: the largest upload and how many decodes run at once
    log_upload_max_mb: int = Field(default=256, ge=1)
    log_decodes_max: int = Field(default=2, ge=1)

    # Scope: captures stream live to the app's own rerun server (loopback) as well as to their
    # .rrd files; off, captures are only recorded (the viewer can still open them)
    scope_live_view: bool = True

    # What the data directory keeps: decoded logs and scope captures beyond these quotas go,
    # oldest first; a capture ends when the disk's free space falls below data_min_free_mb
    # (the audit log and the timeline must still be written)
    logs_keep_mb: int = Field(default=2048, ge=1)
    captures_keep_mb: int = Field(default=8192, ge=1)
    data_min_free_mb: int = Field(default=512, ge=0)

    # Files: uploaded object dictionaries live here, per node
    data_dir: Path = Field(default_factory=default_data_dir)
