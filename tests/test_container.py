"""The container image, for real: run it, feed it over zenoh from the host, query it,
check its health command, stop it with SIGTERM.

Runs when FACING_TEST_IMAGE names a built image (and DOCKER_HOST, if needed, the engine):
.ci/container builds one and sets FACING_TEST_REQUIRE_IMAGE=1, so in CI a missing image or
engine fails instead of skipping.
"""

from __future__ import annotations

import json
import os
import subprocess
import time

import pytest

from loopback import endpoint, free_port, get, send, wait_until_answered
from poses import pose_json

pytestmark = pytest.mark.slow  # processes, recordings or seconds-long scenarios


IMAGE = os.environ.get("FACING_TEST_IMAGE")

if not IMAGE:
    if os.environ.get("FACING_TEST_REQUIRE_IMAGE") == "1":
        raise RuntimeError("FACING_TEST_REQUIRE_IMAGE=1 but FACING_TEST_IMAGE is not set")
    pytest.skip("no image: set FACING_TEST_IMAGE (see .ci/container)", allow_module_level=True)


def docker(*args: str, check: bool = True, timeout: float = 60) -> subprocess.CompletedProcess:
    return subprocess.run(
        ["docker", *args], capture_output=True, text=True, timeout=timeout, check=check
    )


@pytest.fixture
def container():
    port = free_port()
    name = f"facing-test-{port}"
    docker(
        "run",
        "-d",
        "--name",
        name,
        "--network",
        "host",
        "-e",
        f"FACING_LISTEN=tcp/127.0.0.1:{port}",
        "-e",
        "FACING_NO_MULTICAST_SCOUTING=true",
        "-e",
        "FACING_CFG=scouting/delay:0",
        "-e",
        "FACING_BASE_FRAME=base_link",
        "-e",
        "FACING_INSTANCE=in-a-container",
        IMAGE,
    )
    try:
        yield name, port
    finally:
        docker("rm", "-f", name, check=False)


def test_the_image_serves_answers_reports_health_and_stops_on_sigterm(container, net):
    name, port = container
    config = json.loads(docker("inspect", name).stdout)[0]["Config"]
    assert config["User"] == "10001:10001"  # not root
    assert config["Healthcheck"]["Test"][:3] == ["CMD", "facing-service", "health"]

    client = net.client(endpoint(port))
    wait_until_answered(client, "hri/facing/base_link", timeout=30)
    send(client, "hri/bodies/ada/pose/base_link", pose_json("ada", "base_link", off_deg=8.0))
    deadline = time.monotonic() + 10
    while not (replies := get(client, "hri/bodies/*/facing/base_link")):
        assert time.monotonic() < deadline, docker("logs", name).stdout
        time.sleep(0.1)
    ((key, state),) = replies
    assert key == "hri/bodies/ada/facing/base_link"
    assert state["facing"] and state["angle_deg"] == pytest.approx(8.0)
    (frame,) = get(client, "hri/facing/base_link?threshold_deg=5")
    assert frame[1]["bodies_facing"] == []  # a what-if query, answered by the container

    health = docker("exec", name, "facing-service", "health", "--json", check=False)
    assert health.returncode == 0, health.stderr
    assert json.loads(health.stdout.splitlines()[0])["instance"] == "in-a-container"

    started = time.monotonic()
    docker("stop", "--time", "10", name)  # SIGTERM, then SIGKILL after 10 s
    elapsed = time.monotonic() - started
    state = json.loads(docker("inspect", name).stdout)[0]["State"]
    logs = docker("logs", name).stdout + docker("logs", name).stderr
    print(f"\ncontainer stop: exit {state['ExitCode']} after {elapsed:.2f} s")
    assert state["ExitCode"] == 0, logs
    assert elapsed < 2.0 + 0.5, logs  # the contract's 2 s, plus docker's own round trip
    assert "received SIGTERM" in logs
