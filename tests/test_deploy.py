"""Running it beside a robot for good (deploy/): the systemd units are valid units whose
commands the CLI accepts, the one settings file is valid settings, and the service the
unit starts is the one its health check finds healthy (and the check fails without it)."""

from __future__ import annotations

import configparser
import os
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from facing_service.arguments import build_parser
from facing_service.config.sources import load_settings
from facing_service.testing import endpoint, running_cli

from system_packages import require

ROOT = Path(__file__).resolve().parent.parent
DEPLOY = ROOT / "deploy"
UNITS = sorted((DEPLOY / "systemd").glob("facing-service*"))
BINARY = "/opt/facing-service/.venv/bin/facing-service"


SETTINGS_FILES = ("facing-service.env", "facing-service.json.env")


def env_file(name: str = "facing-service.env") -> dict[str, str]:
    pairs = [
        line.split("=", 1)
        for line in (DEPLOY / name).read_text().splitlines()
        if line.strip() and not line.startswith("#")
    ]
    return {k: v for k, v in pairs}


def unit(name: str) -> configparser.ConfigParser:
    parser = configparser.ConfigParser(interpolation=None, strict=False)
    parser.optionxform = str  # type: ignore[assignment,method-assign]
    parser.read(DEPLOY / "systemd" / name)
    return parser


def test_the_settings_file_is_valid_settings_for_a_robot():
    settings = load_settings({}, env_file())
    assert (settings.input, settings.output, settings.mode) == ("ros2", "ros2", "client")
    assert settings.no_multicast_scouting
    plain = load_settings({}, env_file("facing-service.json.env"))  # a JSON body tracker
    assert (plain.input, plain.output, plain.mode) == ("json", "json", "client")
    assert plain.connect == env_file()["FACING_CONNECT"].split(",")


@pytest.mark.parametrize("name", SETTINGS_FILES)
def test_a_shell_reads_the_settings_file_as_systemd_does(name):
    """A defect found: an unquoted `;` made the shipped file fail when sourced (`set -a; .`)."""
    done = subprocess.run(
        ["bash", "-c", f"set -ae; . {shlex.quote(str(DEPLOY / name))}; env -0"],
        capture_output=True,
        text=True,
        env={"PATH": os.environ["PATH"]},
        timeout=10,
    )
    assert done.returncode == 0 and not done.stderr, done.stderr
    sourced = dict(item.split("=", 1) for item in done.stdout.split("\0") if "=" in item)
    assert {k: sourced.get(k) for k in env_file(name)} == env_file(name)


def test_the_service_unit_restarts_on_failure_and_runs_a_command_the_cli_accepts():
    service = unit("facing-service.service")["Service"]
    assert service["Restart"] == "on-failure"
    assert service["EnvironmentFile"] == "/etc/facing-service/facing-service.env"
    command = shlex.split(service["ExecStart"])
    assert command[0] == BINARY
    build_parser().parse_args(command[1:])
    health = unit("facing-service-health.service")["Service"]["ExecStart"]
    inner = shlex.split(shlex.split(health)[2])  # /bin/sh -c '<this>'
    assert inner[0] == BINARY and "restart" in inner and "facing-service.service" in inner
    build_parser().parse_args(inner[1 : inner.index("||")])
    assert unit("facing-service-health.timer")["Timer"]["OnUnitActiveSec"] == "15s"
    # a oneshot with no start timeout that hangs stops its timer from firing again
    assert unit("facing-service-health.service")["Service"]["TimeoutStartSec"] == "30"
    router = shlex.split(unit("facing-service-router.service")["Service"]["ExecStart"])
    assert router[0] == BINARY
    assert build_parser().parse_args(router[1:]).listen == ["tcp/127.0.0.1:7447"]


def test_systemd_accepts_the_units(tmp_path):
    """systemd's own verifier, on copies whose binary and settings file exist here."""
    require("systemd")
    env = tmp_path / "facing-service.env"
    env.write_text((DEPLOY / "facing-service.env").read_text())
    for path in UNITS:
        text = path.read_text().replace(BINARY, shutil.which("facing-service") or sys.executable)
        text = text.replace("/etc/facing-service/facing-service.env", str(env))
        (tmp_path / path.name).write_text(text)
    done = subprocess.run(
        ["systemd-analyze", "verify", "--man=no", *(str(tmp_path / p.name) for p in UNITS)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    complaints = [
        line
        for line in done.stderr.splitlines()
        if tmp_path.name in line or "facing-service" in line
    ]
    assert not complaints, done.stderr


@pytest.mark.slow
def test_what_the_unit_starts_its_health_check_finds_healthy(net):
    """As systemd runs them: the service with the settings file's variables (its router
    a loopback one here), then the health unit's command, which passes; with the service
    stopped, the same command fails (and the unit would restart it)."""
    router = net.router()
    variables = env_file() | {
        "FACING_CONNECT": endpoint(router.port),
        "FACING_INPUT": "json",  # no robot here: the JSON input answers health the same
        "FACING_OUTPUT": "json",
    }
    environment = {**os.environ, **variables}

    def health() -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "facing_service", "health", "--timeout", "3"],
            env=environment,
            capture_output=True,
            text=True,
            timeout=60,
        )

    with running_cli("run", env=variables):
        deadline = time.monotonic() + 20
        while (checked := health()).returncode != 0 and time.monotonic() < deadline:
            time.sleep(0.5)
        assert checked.returncode == 0, checked.stdout + checked.stderr
    assert health().returncode == 1
