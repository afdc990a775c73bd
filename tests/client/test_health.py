"""Status queryable, liveliness token, and the 'health' command against a real service."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import threading
import time

import pytest
import zenoh

from facing_service import __version__
from facing_service.client.health import statuses
from facing_service.config.session import probe_config
from facing_service.config.settings import Settings
from facing_service.config.sources import load_settings
from facing_service.contract.poses import Rejection
from facing_service.contract.schemas import ServiceStatus
from facing_service.shell.service import FacingService

from loopback import endpoint, free_port, get, send, wait_until_answered
from poses import pose_json


def test_status_reports_identity_config_counts_and_every_rejection_reason(net):
    service, ep = net.service(instance="robot-7", max_bodies=50)
    client = net.client(ep)
    wait_until_answered(client, "hri/facing/cam")
    for body in ("a", "b"):
        send(client, f"hri/bodies/{body}/pose/cam", pose_json(body, "cam"))
    send(client, "hri/bodies/a/pose/cam", b"garbage")
    wait_until_answered(client, "hri/facing/cam")  # the worker is past those samples
    ((key, raw),) = get(client, "hri/services/facing/*/status")
    assert key == "hri/services/facing/robot-7/status"
    status = ServiceStatus.model_validate(raw)
    assert status.status == "ok" and status.instance == "robot-7"
    assert status.version == __version__ and status.zenoh_id == service.zid
    assert status.uptime_s >= 0
    assert status.config["max_bodies"] == 50 and status.config["base_frame"] == "cam"
    assert status.bodies_tracked == {"cam": 2} and status.bodies_tracked_total == 2
    assert status.counters["samples_accepted"] == 2
    assert set(status.rejected) == {r.value for r in Rejection}
    assert status.rejected["malformed_json"] == 1 and sum(status.rejected.values()) == 1


def test_liveliness_token_lives_exactly_as_long_as_the_service(net):
    service, ep = net.service(instance="robot-8")
    watcher = net.client(ep)
    wait_until_answered(watcher, "hri/facing/cam")
    tokens = [str(r.ok.key_expr) for r in watcher.liveliness().get("hri/services/facing/*")]
    assert tokens == ["hri/services/facing/robot-8"]
    gone = threading.Event()
    sub = watcher.liveliness().declare_subscriber(
        "hri/services/facing/*",
        lambda s: gone.set() if s.kind == zenoh.SampleKind.DELETE else None,
    )
    try:
        service.close()
        assert gone.wait(5), "no liveliness DELETE when the service stopped"
    finally:
        sub.undeclare()


def health(*flags: str, env: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "facing_service", "health", "--timeout", "2", *flags],
        env={**os.environ, **env},
        capture_output=True,
        text=True,
        timeout=30,
    )


@pytest.mark.slow
def test_health_command_configured_like_a_container(net):
    """Only FACING_* variables, the same as the service's: health must not take the
    service's listen port, and finds the service through it on loopback."""
    port = free_port()
    net.service(listen=[endpoint(port)], instance="robot-9")
    env = {
        "FACING_LISTEN": f"tcp/0.0.0.0:{port}",
        "FACING_NO_MULTICAST_SCOUTING": "true",
        "FACING_CFG": "scouting/delay:0",
    }
    ok = health(env=env)
    assert ok.returncode == 0, ok.stderr
    (line,) = ok.stdout.splitlines()  # a defect found: one line on success, not the whole status
    assert line.startswith("ok: instance robot-9 (facing-service ") and "bodies tracked" in line
    # which instance answered, and where the check reached it
    assert f"at tcp/127.0.0.1:{port}, listening on tcp/127.0.0.1:{port}" in line
    whole = health("--json", env=env)
    assert json.loads(whole.stdout.splitlines()[0])["instance"] == "robot-9"
    assert health(env={**env, "FACING_INSTANCE": "robot-9"}).returncode == 0
    other = health(env={**env, "FACING_INSTANCE": "someone-else"})
    assert other.returncode == 1
    # a defect found: it hinted at the namespace; the instances that are there are named
    assert (
        "no facing service of instance 'someone-else' at tcp/127.0.0.1:"
        f"{port} in namespace 'hri'; instances there: robot-9 (--instance"
    ) in other.stderr, other.stderr
    # a defect found: "1 bodies", "1 samples"
    assert re.search(r"\b0 bodies tracked \(0 in cam\), 0 samples refused", line), line


def test_health_fails_when_nothing_runs():
    port = free_port()
    proc = health("-e", endpoint(port), env={"FACING_NO_MULTICAST_SCOUTING": "1"})
    assert proc.returncode == 1 and len(proc.stderr.splitlines()) == 1
    assert f"tcp/127.0.0.1:{port}" in proc.stderr


def scouting_on_loopback() -> list[str]:
    """Multicast scouting that stays on this machine: interface lo, a private group port."""
    return [
        f'scouting/multicast/address:"224.0.0.224:{free_port()}"',
        'scouting/multicast/interface:"lo"',
        "scouting/delay:0",
    ]


def test_health_by_scouting_says_so_and_which_instance_answered():
    """A defect found: a plain health found another service on the host by scouting and said
    only "ok: instance vm-…"; finding none, it gave no hint of -e."""
    cfg = scouting_on_loopback()
    service = FacingService(Settings(instance="elsewhere", cfg=cfg, log_level="WARNING")).start()
    try:
        found = health(*(f"--cfg={c}" for c in cfg), env={})
    finally:
        service.close()
    assert found.returncode == 0, found.stderr
    assert found.stdout.startswith("ok: instance elsewhere (facing-service ")
    assert "found by multicast scouting" in found.stdout
    none = health(*(f"--cfg={c}" for c in scouting_on_loopback()), env={})
    assert none.returncode == 1 and len(none.stderr.splitlines()) == 1
    assert "found by multicast scouting" in none.stderr
    assert "-e tcp/<host>:<port> --no-multicast-scouting" in none.stderr


def test_health_finds_a_running_peer_mode_service_every_time(net):
    """Default peer mode, discovering the service by multicast scouting, with
    scouting/delay:0 as the README's examples set it, a fresh session each time as a
    container's check runs: a query sent at once missed the service about 1 time in 10
    (measured: 18 of 20). Waiting for its token first: 100 of 100.

    Multicast stays on this machine: interface lo, a private group port."""
    cfg = scouting_on_loopback()
    service = FacingService(Settings(instance="peer-1", cfg=cfg, log_level="WARNING")).start()
    try:
        settings = load_settings({"cfg": cfg}, {})
        answered = 0
        for _ in range(100):
            with zenoh.open(probe_config(settings, 3.0)) as session:
                answers, _alive = statuses(session, "hri", "*", timeout=3.0)
            answered += [a.instance for a in answers] == ["peer-1"]
    finally:
        service.close()
    assert answered == 100


@pytest.mark.parametrize(
    "waiting",
    [{}, {"FACING_CFG": "connect/timeout_ms:-1;connect/exit_on_failure:false"}],
    ids=["plain", "service-waits-for-its-router"],
)
def test_health_without_a_service_fails_within_its_timeout(waiting):
    """A defect found: under the settings of a service that waits for its router for ever (the
    shipped deploy and compose files set them), health hung until killed: one shot, it
    bounds its own session by --timeout whatever the settings say."""
    started = time.monotonic()
    env = {"FACING_NO_MULTICAST_SCOUTING": "1", **waiting}
    proc = health("-m", "client", "-e", endpoint(free_port()), env=env)
    took = time.monotonic() - started
    assert proc.returncode == 1 and len(proc.stderr.strip().splitlines()) == 1
    said = proc.stderr
    assert "cannot open the zenoh session" in said and "--connect" in said  # a client: at once
    assert took < 2.0 + 5.0  # --timeout 2, plus the interpreter's start-up


def test_status_reports_what_the_session_is_connected_to(net):
    service, ep = net.service(instance="linked")
    client = net.client(ep)
    wait_until_answered(client, "hri/facing/cam")
    ((_, raw),) = get(client, "hri/services/facing/*/status")
    assert raw["connected"]["peers"] == [str(client.zid())]
    assert service.connected()["routers"] == []


def test_health_through_a_router_with_no_service_names_the_endpoint_and_the_flags(net):
    """A defect found: the router answers but no service is behind it: the line names the
    endpoint reached and the flags that reach a service elsewhere."""
    router = net.router()
    proc = health(
        "-m", "client", "-e", endpoint(router.port), env={"FACING_NO_MULTICAST_SCOUTING": "1"}
    )
    assert proc.returncode == 1 and len(proc.stderr.splitlines()) == 1
    assert f"at {endpoint(router.port)} in 2 s" in proc.stderr and "--namespace" in proc.stderr


def test_ctrl_c_ends_health_while_its_session_still_connects():
    """A defect found: health ignored Ctrl-C while zenoh.open waited for an endpoint that is not
    there (15.6 s of a --timeout 15, nothing printed); every other command stops at once.
    Interrupted after a second, it ends as a shell reports Ctrl-C, long before its timeout."""
    args = ["health", "--timeout", "30", "-m", "client", "-e", endpoint(free_port())]
    proc = subprocess.Popen(
        [sys.executable, "-m", "facing_service", *args, "--no-multicast-scouting"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    time.sleep(1.5)  # inside zenoh.open by now (the interpreter starts in well under that)
    proc.send_signal(signal.SIGINT)
    try:
        out, err = proc.communicate(timeout=15)  # half its own timeout
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        pytest.fail("health went on connecting after Ctrl-C")
    assert proc.returncode == 130 and "Traceback" not in out + err, err


def test_health_says_a_silent_input_and_how_many_it_holds():
    """A defect found: the status said ok throughout a stall, and nothing else did."""
    from facing_service.client.health import summary
    from facing_service.contract.schemas import InputHealth

    status = ServiceStatus(
        status="ok", instance="edge", version="1", zenoh_id="z", uptime_s=60.0, config={},
        bodies_tracked={"base_link": 3}, bodies_tracked_total=3, counters={}, rejected={},
        inbox_depth=0, outbox_depth=0,
        input=InputHealth(last_heard_s=3.2, silent=True, held=3, silences=1,
                          longest_silence_s=0.0),
    )  # fmt: skip
    line = summary(status, "reached at tcp/127.0.0.1:7447")
    assert line.endswith(", its input silent for 3.2 s (3 people held)"), line
    heard = status.model_copy(update={"input": InputHealth(
        last_heard_s=0.03, silent=False, held=0, silences=1, longest_silence_s=4.0)})  # fmt: skip
    assert "silent" not in summary(heard, "reached at tcp/127.0.0.1:7447")


def test_require_input_fails_while_nothing_works_and_says_why(net):
    """Before: health said ok, exit 0, while the input was silent or a ROS 2 robot's /tf
    did not reach the base frame: a container health check passed while nothing worked."""
    from facing_service.client.health import input_broken
    from facing_service.contract.schemas import InputHealth, Ros2Status

    status = ServiceStatus(
        status="ok", instance="edge", version="1", zenoh_id="z", uptime_s=60.0, config={},
        bodies_tracked={}, bodies_tracked_total=0, counters={}, rejected={},
        inbox_depth=0, outbox_depth=0,
        input=InputHealth(last_heard_s=0.1, silent=False, held=0, silences=0,
                          longest_silence_s=0.0),
    )  # fmt: skip
    assert input_broken(status) is None
    silent = status.model_copy(update={"input": status.input.model_copy(update={"silent": True})})
    assert input_broken(silent) == "its input is silent"
    ros = Ros2Status.model_construct(findings={"base_frame_not_in_tree": "...", "x": "..."})
    lost = status.model_copy(update={"ros2": ros})
    assert input_broken(lost) == "its ROS 2 input: base_frame_not_in_tree"
    port = free_port()
    net.service(listen=[endpoint(port)], instance="robot-7")
    env = {"FACING_LISTEN": f"tcp/127.0.0.1:{port}", "FACING_NO_MULTICAST_SCOUTING": "true"}
    assert health("--require-input", env=env).returncode == 0  # nobody tracked: not silent
