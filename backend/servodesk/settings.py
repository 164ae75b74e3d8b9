"""All settings in one place: environment variables `SERVODESK_*`, then CLI flags override."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import Field
from pydantic_settings import BaseSettings, SettingsConfigDict


class Settings(BaseSettings):
    model_config = SettingsConfigDict(env_prefix="SERVODESK_", extra="ignore")

    # Where the web app listens. Beyond loopback needs a token (a later issue); refuse until then.
    bind: str = "127.0.0.1"
    port: int = 8000

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

    # Files: uploaded object dictionaries live here, per node
    data_dir: Path = Path.home() / ".local" / "share" / "servodesk"
