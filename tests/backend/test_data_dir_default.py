"""The default data directory: the platform's user data directory (platformdirs), with an
earlier version's ~/.local/share/servodesk kept where it holds data."""

from __future__ import annotations

from pathlib import Path

import pytest

from servodesk import settings
from servodesk.settings import Settings, default_data_dir


def test_linux_default_is_unchanged(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.delenv("XDG_DATA_HOME", raising=False)
    monkeypatch.setattr("sys.platform", "linux")
    assert default_data_dir() == tmp_path / ".local" / "share" / "servodesk"


def test_settings_take_the_default_and_the_environment(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.setattr(settings, "user_data_path", lambda *_, **__: tmp_path / "platform")
    monkeypatch.delenv("SERVODESK_DATA_DIR", raising=False)
    assert Settings().data_dir == tmp_path / "platform"
    monkeypatch.setenv("SERVODESK_DATA_DIR", str(tmp_path / "mine"))
    assert Settings().data_dir == tmp_path / "mine"


@pytest.mark.parametrize("earlier_exists", [True, False])
def test_an_earlier_data_directory_is_kept(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, earlier_exists: bool
) -> None:
    """As on Windows or macOS, where the platform's directory is elsewhere."""
    monkeypatch.setenv("HOME", str(tmp_path))
    earlier = tmp_path / ".local" / "share" / "servodesk"
    if earlier_exists:
        earlier.mkdir(parents=True)
    platform = tmp_path / "AppData" / "Local" / "servodesk"
    monkeypatch.setattr(settings, "user_data_path", lambda *_, **__: platform)
    assert default_data_dir() == (earlier if earlier_exists else platform)
