"""The real CLI process: configured by flags and FACING_* variables, stopped by signals."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import pytest

from facing_service import __version__
from facing_service.schemas import json_schemas
from facing_service.testing import LOOPBACK_FLAGS, running_cli

from loopback import endpoint, free_port, get, send, wait_until_answered
from poses import pose_json


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_signal_stops_the_real_process_cleanly(net, signum):
    port = free_port()
    env = {"FACING_BASE_FRAME": "cam", "FACING_THRESHOLD_DEG": "33"}
    with running_cli("run", "-l", endpoint(port), *LOOPBACK_FLAGS, env=env) as proc:
        client = net.client(endpoint(port))
        wait_until_answered(client, "hri/facing/cam")
        send(client, "hri/bodies/a/pose/cam", pose_json("a", "cam", off_deg=30.0))
        deadline = time.monotonic() + 5
        while not (replies := get(client, "hri/bodies/a/facing/cam")):
            assert time.monotonic() < deadline, "the CLI never published a result"
            time.sleep(0.05)
        assert replies[0][1]["facing"] and replies[0][1]["threshold_deg"] == 33.0  # env used
        started = time.monotonic()
        proc.send_signal(signum)
        code = proc.wait(timeout=5)
        elapsed = time.monotonic() - started
        output = proc.stdout.read()
    assert code == 0, output
    # The contract's deadline (typically ~0.1 s here), not a performance measurement.
    assert elapsed < 2.0, f"took {elapsed:.2f} s to stop"
    first_line = output.splitlines()[0]
    assert f"facing-service {__version__} started: instance " in first_line
    assert "zenoh id " in first_line
    assert "hri/bodies/*/pose/cam" in first_line


@pytest.mark.parametrize(
    ("flags", "code", "message"),
    [
        (["--threshold-deg", "500"], 2, "--threshold-deg=500.0: "),  # our settings
        (["--cfg", "no/such/key:1"], 2, "--cfg no/such/key:<redacted>: unknown zenoh config"),
    ],
    ids=["invalid-setting", "bad-zenoh-config"],
)
def test_refused_configuration_exits_with_a_message(flags, code, message):
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "run", *flags],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == code
    assert message in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1, "one line, no traceback"


def test_export_schemas_writes_every_schema(tmp_path):
    subprocess.run(
        [sys.executable, "-m", "facing_service", "export-schemas", str(tmp_path)],
        check=True,
        timeout=30,
    )
    written = {p.name: json.loads(p.read_text()) for p in tmp_path.iterdir()}
    assert written == json_schemas()
    assert "status.schema.json" in written and "pose.schema.json" in written


def test_sigterm_while_still_waiting_for_a_router_exits_cleanly():
    """With connect/timeout_ms:-1 (as compose.yaml sets), zenoh.open waits for a router
    that may never come; SIGTERM must still end the process at once (docker stop)."""
    flags = (
        "-m",
        "client",
        "-e",
        endpoint(free_port()),
        *LOOPBACK_FLAGS,
        "--cfg",
        "connect/timeout_ms:-1",
        "--cfg",
        "connect/exit_on_failure:false",
    )
    with running_cli("run", *flags) as proc:
        time.sleep(1.5)  # zenoh is busy retrying the dead endpoint
        assert proc.poll() is None
        started = time.monotonic()
        proc.send_signal(signal.SIGTERM)
        code = proc.wait(timeout=10)
        elapsed = time.monotonic() - started
        output = proc.stdout.read()
    assert code == 0, output
    assert elapsed < 2.0, f"took {elapsed:.2f} s"  # the contract's deadline
