"""The wheel as a user gets it: `python -m build` makes the sdist and, from it, the wheel; the
wheel goes into a fresh virtual environment with its declared dependencies (no checkout, no
Node), and that environment's own `servodesk serve --sim` serves the API and the built page.

One build and one install: uv installs the wheel where `make` put it beside the tests (the same
resolution of the declared ranges as pip's, from its warm cache: seconds instead of most of a
minute), pip where it did not. Everything happens in a temporary directory, so the checkout
gets no build/ or *.egg-info."""

from __future__ import annotations

import os
import re
import shutil
import socket
import subprocess
import sys
import tarfile
import time
import zipfile
from pathlib import Path

import httpx
import pytest

import servodesk

pytestmark = pytest.mark.packaging

ROOT = Path(__file__).resolve().parents[2]
SOURCES = ("pyproject.toml", "README.md", "backend", "sim")
INDEX = ROOT / "backend" / "servodesk" / "static" / "index.html"
START_TIMEOUT_S = 120.0

# What the wheel must carry besides the modules: the built page, the commissioning report's
# template, the drives' data, the typing markers of each package.
PACKAGE_DATA = (
    "servodesk/static/index.html",
    "servodesk/commissioning/templates/report.html.j2",
    "servodesk/commissioning/templates/report.css",
    "servodesk/py.typed",
    "servodesk_sim/py.typed",
    "servodesk_protocol/py.typed",
    "servodesk_data/py.typed",
    "servodesk_data/mdi-s1c/drive.eds",
    "servodesk_data/mdi-s1c/profile.toml",
    "servodesk_data/kinco/drive.eds",
    "servodesk_data/kinco/profile.toml",
    "servodesk_data/cia402/drive.eds",
    "servodesk_data/cia402/profile.toml",
    "servodesk_data/cia402/recommended_pdos.toml",
)


def _scripts(venv: Path) -> Path:
    return venv / ("Scripts" if os.name == "nt" else "bin")


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def _run(command: list[str | Path], cwd: Path, env: dict[str, str]) -> str:
    done = subprocess.run(
        [str(part) for part in command],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode != 0:
        pytest.fail(f"{' '.join(map(str, command))} failed:\n{done.stdout}\n{done.stderr}")
    return done.stdout


def _clean_environment(home: Path) -> dict[str, str]:
    """The user's environment without anything that points back into the checkout."""
    env = {
        key: value
        for key, value in os.environ.items()
        if not key.startswith(("SERVODESK_", "PYTHON", "VIRTUAL_ENV", "PYTEST"))
    }
    env["SERVODESK_DATA_DIR"] = str(home / "data")
    return env


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The sdist and the wheel, built from a copy of the sources."""
    if not INDEX.is_file():
        pytest.fail(f"{INDEX} is missing: build the frontend first (npm run build; make does)")
    work = tmp_path_factory.mktemp("build")
    source = work / "source"
    source.mkdir()
    for name in SOURCES:
        if (ROOT / name).is_dir():
            shutil.copytree(
                ROOT / name,
                source / name,
                ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info"),
            )
        else:
            shutil.copy2(ROOT / name, source / name)
    dist = work / "dist"
    _run([sys.executable, "-m", "build", "--outdir", dist, source], work, dict(os.environ))
    (sdist,) = dist.glob("servodesk-*.tar.gz")
    (wheel,) = dist.glob("servodesk-*.whl")
    return sdist, wheel


@pytest.mark.timeout(900)
def test_sdist_and_wheel_carry_the_page_and_the_data(built: tuple[Path, Path]) -> None:
    sdist, wheel = built
    version = servodesk.__version__
    assert wheel.name.startswith(f"servodesk-{version}-py3-none-any")
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
        metadata = archive.read(f"servodesk-{version}.dist-info/METADATA").decode()
    missing = [name for name in PACKAGE_DATA if name not in names]
    assert not missing, f"not in the wheel: {missing}"
    assert any(re.fullmatch(r"servodesk/static/assets/.+\.js", name) for name in names)
    assert {name.split("/")[0] for name in names if "/" in name} == {
        "servodesk",
        "servodesk_sim",
        "servodesk_data",
        "servodesk_protocol",
        f"servodesk-{version}.dist-info",
    }, "the wheel installs only ServoDesk's own packages (no backend/, sim/, tests/)"
    assert f"Version: {version}\n" in metadata
    with tarfile.open(sdist) as archive:
        sdist_names = {name.split("/", 1)[-1] for name in archive.getnames()}
    assert "backend/servodesk/static/index.html" in sdist_names
    assert "sim/servodesk_data/kinco/drive.eds" in sdist_names


@pytest.mark.timeout(900)
def test_wheel_serves_the_app_from_a_clean_virtual_environment(
    built: tuple[Path, Path], tmp_path: Path
) -> None:
    _, wheel = built
    venv, home, outside = tmp_path / "venv", tmp_path / "home", tmp_path / "elsewhere"
    home.mkdir()
    outside.mkdir()
    env = _clean_environment(home)
    uv = shutil.which("uv", path=str(Path(sys.executable).parent))
    _run([sys.executable, "-m", "venv", *(["--without-pip"] if uv else []), venv], outside, env)
    python = _scripts(venv) / ("python.exe" if os.name == "nt" else "python")
    # the wheel's declared dependencies, resolved by the installer (never --no-deps)
    if uv:
        _run([uv, "pip", "install", "--quiet", "--python", python, wheel], outside, env)
    else:
        _run([python, "-m", "pip", "install", "--quiet", wheel], outside, env)

    where = _run(
        [python, "-c", "import servodesk, servodesk_data; print(servodesk.__file__)"], outside, env
    )
    assert Path(where.strip()).is_relative_to(venv), f"imported from {where}, not the venv"
    assert ROOT not in Path(where.strip()).parents

    port = _free_port()
    servodesk_script = _scripts(venv) / ("servodesk.exe" if os.name == "nt" else "servodesk")
    log_path = tmp_path / "serve.log"
    with log_path.open("wb") as log:
        server = subprocess.Popen(
            [str(servodesk_script), "serve", "--sim", "--bind", "127.0.0.1", "--port", str(port)],
            cwd=outside,
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=log,
            stderr=subprocess.STDOUT,
        )
    base = f"http://127.0.0.1:{port}"
    try:
        with httpx.Client(base_url=base, trust_env=False, timeout=10.0) as client:
            health = None
            deadline = time.monotonic() + START_TIMEOUT_S
            while time.monotonic() < deadline and server.poll() is None:
                try:
                    health = client.get("/api/health")
                    break
                except httpx.TransportError:
                    time.sleep(0.3)
            if health is None:
                pytest.fail(
                    f"servodesk serve --sim did not answer on {base} (exit {server.poll()}):\n"
                    + log_path.read_text(errors="replace")[-3000:]
                )
            assert health.status_code == 200, health.text
            assert health.json()["version"] == servodesk.__version__

            page = client.get("/")
            assert page.status_code == 200, page.text[:500]
            assert page.headers["content-type"].startswith("text/html")
            assert page.text == INDEX.read_text(encoding="utf-8"), "not the built index.html"
            script = re.search(r'src="(/assets/[^"]+\.js)"', page.text)
            assert script is not None, page.text[:500]
            asset = client.get(script.group(1))
            assert asset.status_code == 200
            assert "javascript" in asset.headers["content-type"]
    finally:
        server.terminate()
        try:
            server.wait(20)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()
