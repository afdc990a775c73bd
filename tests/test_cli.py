"""The real CLI process: configured by flags and FACING_* variables, stopped by signals."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
import zenoh

from facing_service import __version__
from facing_service.contract.schemas import json_schemas
from facing_service.testing import LOOPBACK_FLAGS, running_cli

from loopback import (
    endpoint,
    free_port,
    get,
    loopback_config,
    results,
    send,
    wait_until,
    wait_until_answered,
)
from oracles import BAGS
from poses import pose_json
from routers import Router

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_signal_stops_the_real_process_cleanly(net, signum):
    port = free_port()
    env = {"FACING_BASE_FRAME": "cam", "FACING_THRESHOLD_DEG": "33"}
    with running_cli("run", "-l", endpoint(port), *LOOPBACK_FLAGS, env=env) as proc:
        client = net.client(endpoint(port))
        wait_until_answered(client, "hri/facing/cam")
        send(client, "hri/bodies/a/pose/cam", pose_json("a", "cam", off_deg=30.0))
        deadline = time.monotonic() + 5
        while not (replies := results(get(client, "hri/bodies/a/facing/cam"))):
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
    ("flags", "env", "code", "message"),
    [
        (["--threshold-deg", "500"], {}, 2, "--threshold-deg=500.0: "),  # our settings
        (["--cfg", "no/such/key:1"], {}, 2, "--cfg no/such/key:<redacted>: unknown zenoh config"),
        # a defect found: named --cfg though no flag was given
        ([], {"FACING_CFG": "no/such/key:1"}, 2, "FACING_CFG no/such/key:<redacted>: unknown"),
    ],
    ids=["invalid-setting", "bad-zenoh-config", "bad-zenoh-config-variable"],
)
def test_refused_configuration_exits_with_a_message(flags, env, code, message):
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "run", *flags],
        capture_output=True,
        text=True,
        timeout=30,
        env={**os.environ, **env},
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


@pytest.mark.slow
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


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["simulate", "--rate-hz", "0"], "argument --rate-hz: must be a number > 0, got 0"),
        (["simulate", "--rate-hz", "-5"], "argument --rate-hz: must be a number > 0, got -5"),
        (["demo", "--rate-hz", "0"], "argument --rate-hz: must be a number > 0, got 0"),
        (["camera", "--reach-m", "0.1"], "argument --reach-m: must be a number >= 0.5, got 0.1"),
        (["camera", "--reach-m", "50"], "argument --reach-m: must be a number <= 20, got 50"),
        # a defect found: the rule named the fields, not the flags
        (
            ["run", "--disengage-below", "0.7", "--engage-above", "0.6"],
            "--disengage-below (FACING_DISENGAGE_BELOW, 0.7) must be below --engage-above "
            "(FACING_ENGAGE_ABOVE, 0.6)",
        ),
        # a defect found: the camera's flags were ignored by a demo of simulated people
        (["demo", "--calibration", "ci.yaml"], "demo: --calibration only with --camera"),
        (["demo", "--fov-deg", "90", "--max-faces", "2"], "--fov-deg and --max-faces only with"),
        (["simulate", "--people", "-1"], "argument --people: must be a number >= 1, got -1"),
        (["health", "--timeout", "-1"], "argument --timeout: must be a number > 0, got -1"),
        (["watch", "--wait-s", "nan"], "argument --wait-s: must be a number >= 0, got nan"),
        (["export-schemas", "/proc/nope"], "export-schemas: /proc/nope: No such file or directory"),
        (
            ["run", "-e", "tcp/nohost:99999"],
            "--connect=['tcp/nohost:99999']: tcp/nohost:99999: port",
        ),
        (["run", "-e", "nohost:7447"], "not <protocol>/<address> (tcp/nohost:7447?)"),
        (["run", "-l", "tcp/[::1:7447"], "--listen="),
        (["run", "-c", "/no/such.json5"], "--config '/no/such.json5': no such file"),
        (["run", "-c", "/tmp"], "--config '/tmp': not a file"),
        (["run", "--threshold", "30"], "unrecognized arguments: --threshold 30 (did you mean "),
        # a misspelt flag gets the nearest, as a misspelt FACING_ variable does
        (["run", "--treshold-deg", "30"], "--treshold-deg 30 (did you mean --threshold-deg?)"),
        # a defect found: nan was said as "Input should be less than 180"
        (["run", "--threshold-deg", "nan"], "--threshold-deg=nan: Input should be a finite"),
        (["run", "--stale-after-s", "inf"], "--stale-after-s=inf: Input should be a finite"),
    ],
)
def test_every_number_path_and_endpoint_is_checked_in_one_line(args, message):
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", *args], capture_output=True, text=True, timeout=30
    )
    assert proc.returncode == 2, proc.stderr
    assert message in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr


@pytest.mark.slow
def test_simulate_says_what_it_publishes(net):
    service, ep = net.service()
    for _ in range(2):  # a defect found: a second run was refused as out_of_order (a fixed clock)
        _simulate_once(ep)
    assert service.status().rejected["out_of_order"] == 0
    assert service.status().counters["clock_restarts"] == 0


def _simulate_once(ep: str) -> None:
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "facing_service",
            "simulate",
            "--duration-s",
            "0.3",
            "--base-frame",
            "cam",  # the test service's frame: poses on base_link went to nobody, unseen
            "-e",
            ep,
            *LOOPBACK_FLAGS,
        ],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 0, proc.stderr
    first, last = proc.stdout.strip().splitlines()
    assert first.startswith("simulating 5 people: poses on hri/bodies/<id>/pose/cam at 30 Hz")
    assert last.startswith("published ") and " poses and " in last
    assert not last.endswith(" 0 heard by a subscriber"), last


@pytest.mark.slow
def test_simulate_to_nowhere_says_nobody_heard_and_fails():
    """A defect found: publishing to an endpoint nobody listens on said "published 900 poses"
    and exited 0; zenoh's matching status says nobody heard them."""
    ep = endpoint(free_port())
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "simulate", "--duration-s", "1", "-e", ep,
         *LOOPBACK_FLAGS],
        capture_output=True, text=True, timeout=30,
    )  # fmt: skip
    assert proc.returncode == 1, proc.stdout
    assert proc.stdout.strip().endswith(" 0 heard by a subscriber"), proc.stdout
    assert proc.stderr.startswith("facing-service simulate: no subscriber heard any pose")
    assert f"reachable at {ep}?" in proc.stderr and len(proc.stderr.splitlines()) == 1


def test_a_peer_says_at_once_that_its_endpoints_are_unreachable(caplog):
    """A defect found: a peer told to connect to an endpoint nobody listens on was silent for
    10 s; the service's link watch says so within about a second, and the status shows
    how long it has had nobody."""
    import logging

    from facing_service.config.settings import Settings
    from facing_service.shell.service import FacingService

    caplog.set_level(logging.WARNING, logger="facing_service")
    settings = Settings(
        connect=[endpoint(free_port())], no_multicast_scouting=True, cfg=["scouting/delay:0"]
    )
    with FacingService(settings) as service:
        wait_until(lambda: "no router or peer reachable at tcp/127.0.0.1:" in caplog.text,
                   5, "the warning")  # fmt: skip
        assert service.status().outage_s is not None


@pytest.mark.slow
def test_run_in_client_mode_waits_for_its_router_and_says_so(tmp_path):
    """A defect found: `run -m client` exited at once when the router was not up yet, so a robot
    booting in any order needed a restart. It now waits, says so within a second (and how
    to exit instead), and answers once the router comes up."""
    port = free_port()
    ep = endpoint(port)
    with running_cli("run", "-m", "client", "-e", ep, "--no-multicast-scouting") as proc:
        time.sleep(2.0)
        assert proc.poll() is None, proc.communicate()[0]
        router = Router(str(loopback_config(listen=[ep], mode="router")), port).start()
        try:
            with zenoh.open(loopback_config(connect=[ep], mode="client")) as session:
                wait_until(
                    lambda: any(r.ok for r in session.get("hri/services/facing/*/status")),
                    20, "the service's status through the router",
                )  # fmt: skip
        finally:
            proc.send_signal(signal.SIGTERM)
            output, _ = proc.communicate(timeout=10)
            router.stop()
    assert proc.returncode == 0, output
    assert "still waiting for a router at " + ep in output
    assert "--exit-without-router exits instead" in output
    assert "the router answered after" in output


@pytest.mark.slow
@pytest.mark.parametrize("viewer", [("watch",), ("view", "--port", "0")])
def test_a_live_viewer_waits_for_its_router_like_run(viewer, tmp_path):
    """A defect found: watch and view in client mode exited 1 when the router was not up yet,
    while run waited; a live viewer now waits too, says so, and opens once it answers.
    The router starts once the viewer has said it waits (a fixed 2 s was too short for a
    loaded machine's start: the router was up before the viewer first looked, seen in CI)."""
    port = free_port()
    ep = endpoint(port)
    # retrying every 0.2 s (zenoh's own 1 s doubling to 4 s could outwait the test)
    flags = ("-m", "client", "-e", ep, "--no-multicast-scouting", "--reconnect-s", "0.2,0.2")
    said = tmp_path / "output.txt"
    with said.open("w") as out, running_cli(*viewer, *flags, capture=False, stdout=out) as proc:
        wait_until(lambda: "still waiting for a router at " + ep in said.read_text(), 60,
                   "the viewer saying it waits for its router")  # fmt: skip
        assert proc.poll() is None, said.read_text()
        router = Router(str(loopback_config(listen=[ep], mode="router")), port).start()
        try:
            time.sleep(4.0)  # the session opens, the client looks for a service (2 s)
            assert proc.poll() is None, said.read_text()
        finally:
            proc.send_signal(signal.SIGTERM)
            proc.wait(timeout=10)
            router.stop()
    output = said.read_text()
    assert proc.returncode == 0, output
    assert "still waiting for a router at " + ep in output
    assert "Traceback" not in output
    if viewer[0] == "watch":  # its last frame, drawn once the session opened
        assert "0 of 0 facing the robot" in output


@pytest.mark.slow
def test_watch_once_says_at_once_that_no_router_answers():
    """One shot: no waiting, one line naming the command, exit 1."""
    flags = ("-m", "client", "-e", endpoint(free_port()), "--no-multicast-scouting")
    started = time.monotonic()
    with running_cli("watch", "--once", *flags) as proc:
        output, _ = proc.communicate(timeout=20)
    assert proc.returncode == 1 and time.monotonic() - started < 15, output
    assert output.startswith("facing-service watch:") and len(output.splitlines()) == 1, output


@pytest.mark.slow
def test_a_wrong_namespace_is_said_as_such_not_blamed_on_the_router(net):
    """A defect found: with the router (here the service itself) up, a viewer of another
    namespace said "still waiting for a router at …"; it names the namespace now, and
    those that answer. One shot exits 1; a live view goes on waiting for results."""
    port = free_port()
    net.service(listen=[endpoint(port)])
    flags = ("-e", endpoint(port), "--no-multicast-scouting")
    with running_cli("watch", "--once", *flags, "--namespace", "hri2") as proc:
        once, _ = proc.communicate(timeout=20)
    assert proc.returncode == 1, once
    assert once.strip() == (
        f"facing-service watch: no facing service in namespace 'hri2' at {endpoint(port)} "
        "(namespaces with one: hri)"
    )
    with running_cli("view", "--port", "0", *flags, "--namespace", "robot1/hri") as proc:
        time.sleep(4.0)
        proc.send_signal(signal.SIGTERM)
        live, _ = proc.communicate(timeout=10)
    assert f"no facing service in namespace 'robot1/hri' at {endpoint(port)}" in live, live
    assert "waiting for a router" not in live and "Traceback" not in live


@pytest.mark.slow
def test_watch_once_on_a_wrong_port_in_peer_mode_is_one_line_and_fails():
    """A defect found: a peer's session opens with nobody there; one shot drew an empty map,
    blamed the router, spoke of a cache filling, and exited 0."""
    ep = endpoint(free_port())
    with running_cli("watch", "--once", "-e", ep, "--no-multicast-scouting") as proc:
        output, _ = proc.communicate(timeout=20)
    assert proc.returncode == 1, output
    assert output.strip() == (
        f"facing-service watch: nothing answers at {ep}: no router or peer reached (is one "
        "listening there?)"
    )


@pytest.mark.slow
def test_ctrl_c_while_the_command_still_imports_is_quiet():
    """A defect found: Ctrl-C in the first ~0.3 s of `run` printed 15 lines of importlib's
    traceback; the entry point now imports the command's modules where it catches it.
    (The interpreter's own start-up, before any of our code, stays Python's.)"""
    for after_s in (0.15, 0.3, 0.5):
        proc = subprocess.Popen(
            [sys.executable, "-m", "facing_service", "run", "-l", endpoint(free_port()),
             *LOOPBACK_FLAGS],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        )  # fmt: skip
        time.sleep(after_s)
        proc.send_signal(signal.SIGINT)
        output, _ = proc.communicate(timeout=20)
        assert "Traceback" not in output and proc.returncode in (0, 130), (after_s, output)


@pytest.mark.slow
def test_log_level_reaches_zenohs_own_log_but_never_its_debug(monkeypatch):
    """--log-level DEBUG shows zenoh's own log (its info level), never zenoh's debug,
    which prints the session's config, secrets included (see test_router_secure)."""
    # An unreachable endpoint: zenoh itself has something to say about it.
    flags = ("-e", endpoint(free_port()), *LOOPBACK_FLAGS, "--log-level", "DEBUG")
    monkeypatch.delenv("RUST_LOG", raising=False)  # set, it would decide instead
    with running_cli("run", *flags) as proc:
        time.sleep(2.0)
        proc.send_signal(signal.SIGTERM)
        output, _ = proc.communicate(timeout=10)
    zenohs = [line for line in output.splitlines() if "zenoh::" in line or "zenoh_" in line]
    assert zenohs, "zenoh's own log is not shown"
    assert not any("DEBUG" in line or "TRACE" in line for line in zenohs)
    assert "facing-service 0" in output


def test_below_debug_zenohs_warnings_stay_out_of_our_one_line(monkeypatch):
    """A newcomer's connection problem came after zenoh's coloured WARN lines carrying
    the Rust source paths of zenoh's build; our own line is the one to read."""
    monkeypatch.delenv("RUST_LOG", raising=False)
    flags = ("-m", "client", "-e", endpoint(free_port()), "--no-multicast-scouting")
    with running_cli("run", *flags, "--exit-without-router") as proc:
        output, _ = proc.communicate(timeout=30)
    assert proc.returncode == 1, output
    assert " WARN" not in output and ".rs:" not in output, output
    assert "facing-service run: cannot open the zenoh session: Unable to connect" in output


def test_a_port_in_use_is_one_clean_line_naming_listen():
    port = free_port()
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", port))
        taken.listen()
        with running_cli("run", "-l", f"tcp/127.0.0.1:{port}", "--no-multicast-scouting") as proc:
            output, _ = proc.communicate(timeout=30)
    assert proc.returncode == 1, output
    (line,) = [x for x in output.splitlines() if x.startswith("facing-service run:")]
    assert "Address already in use" in line and "--listen" in line and ".rs" not in line


def test_a_bad_flag_is_said_by_its_command_with_its_usage(capsys):
    """`run --bogus` names run and points at run's help, not the top level's."""
    from facing_service.cli import main

    for argv, command in ((["run", "--bogus"], "run"), (["watch", "--threshold", "3"], "watch")):
        with pytest.raises(SystemExit) as exited:
            main(argv)
        assert exited.value.code == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"facing-service {command}: unrecognized arguments: ")
        assert err.endswith(f"(see facing-service {command} --help)")
    # a defect found: the hint came between the flag and its value ("--threshold (did you mean
    # --threshold-deg?) 30")
    with pytest.raises(SystemExit):
        main(["run", "--threshold", "30", "--bogus-flag", "--verbos", "x", "y"])
    err = capsys.readouterr().err
    assert "--threshold 30 (did you mean --threshold-deg?) --bogus-flag --verbos x y" in err, err


def test_every_command_describes_itself():
    from facing_service.arguments import build_parser

    for name, command in build_parser().commands.items():
        assert command.description, f"{name} has no description for --help"


def test_the_result_types_the_docs_name_are_importable_from_the_package():
    import facing_service

    for name in (
        "FacingClient",
        "FacingState",
        "FrameFacing",
        "EngagementState",
        "EngagementEvent",
    ):
        assert hasattr(facing_service, name) and name in facing_service.__all__


def test_the_watch_table_and_the_demo_order_ids_as_numbers():
    from facing_service.contract.keys import natural_order

    ids = ["p10", "p4", "p1", "alice", "p2b", "p2a", "b7"]
    assert sorted(ids, key=natural_order) == ["alice", "b7", "p1", "p2a", "p2b", "p4", "p10"]


@pytest.mark.parametrize(
    "command",
    [
        ["watch", "--once"],
        ["simulate", "--duration-s", "1"],
        ["run"],
        pytest.param(["replay", str(BAGS / "1p_AA_eng_1")], marks=pytest.mark.shared_data),
        ["inspect", "--seconds", "1"],
    ],
    ids=lambda c: c[0],
)
def test_no_router_is_one_line_naming_connect(command):
    """A client with no router fails at once: every command says so in one line that
    names --connect, never a traceback."""
    nobody = endpoint(free_port())
    wait = ["--exit-without-router"] if command == ["run"] else []  # run waits by default
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", *command, "-m", "client", "-e", nobody, *wait],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=ROOT,
    )
    assert proc.returncode == 1, proc.stdout + proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert lines[0].startswith(f"facing-service {command[0]}: cannot open the zenoh session")
    assert nobody in lines[0] and "--connect" in lines[0]


def test_help_log_and_status_say_the_same(net, tmp_path, caplog):
    """The status shows the session's mode and scouting whether a flag or the config file
    set them; the start line says how faces are judged and what goes to the robot; the
    router offers no --mode; --log-level's help lists every level it accepts."""
    import logging

    from facing_service.arguments import build_parser

    port = free_port()
    conf = tmp_path / "service.json5"
    conf.write_text(
        '{mode: "peer", scouting: {multicast: {enabled: false}, delay: 0}, '
        f'listen: {{endpoints: ["{endpoint(port)}"]}}}}'
    )
    caplog.set_level(logging.INFO, "facing_service")
    service, _ = net.service(config=conf, listen=[], input="ros2", output="ros2")
    config = service.status().config
    assert (config["mode"], config["no_multicast_scouting"]) == ("peer", True)
    (started,) = [r.getMessage() for r in caplog.records if "started" in r.getMessage()]
    assert "faces facing within 20.0 deg (3d)" in started
    topics = "engagement_status, facing lists, groups, gazing, markers"
    said = f"ROS 2 output on the robot's topics ({topics})"
    assert said in started
    commands = build_parser().commands
    assert "--mode {" not in commands["router"].format_help()  # its description names it only
    assert "CRITICAL" in commands["run"].format_help().split("--log-level")[-1].split("--")[0]


def test_a_client_waiting_for_its_router_says_so(monkeypatch, caplog):
    """compose.yaml's client waits for its router inside zenoh.open (connect/timeout_ms
    -1), where zenoh says nothing: run warns every period all the same."""
    from facing_service.config import patience
    from facing_service.config.settings import Settings

    monkeypatch.setattr(patience, "UNREACHABLE_WARNING_S", 0.2)
    nobody = endpoint(free_port())
    settings = Settings(mode="client", connect=[nobody], cfg=["connect/timeout_ms:-1"])
    never_opens, stop = threading.Event(), threading.Event()
    timer = threading.Timer(0.7, stop.set)
    timer.start()
    assert patience.wait_until_open(never_opens, settings, stop) is False
    warnings = [
        r.getMessage() for r in caplog.records if "still waiting for a router" in r.getMessage()
    ]
    assert len(warnings) >= 2 and nobody in warnings[0]


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (["--host", "example.com"], "--host: not an IP address: 'example.com'"),
        (["--port", "70000"], "--port: must be a port in 0..65535"),
    ],
    ids=["host", "port"],
)
def test_view_refuses_a_bad_address_naming_the_flag(flags, message):
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "view", *flags],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 2 and message in proc.stderr, proc.stderr


def test_view_says_a_port_in_use_in_one_line(net):
    """The page's port taken (here by a listening socket): one line naming the flags."""
    import socket

    _service, ep = net.service()
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        proc = subprocess.run(
            [sys.executable, "-m", "facing_service", "view", "-e", ep, *LOOPBACK_FLAGS,
             "--port", str(port), "--base-frame", "cam"],
            capture_output=True, text=True, timeout=30,
        )  # fmt: skip
    assert proc.returncode == 1
    assert f"facing-service view: --host 127.0.0.1 --port {port}: " in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr


def test_the_camera_publishes_in_the_frame_the_views_and_the_service_default_to():
    """A defect found: camera published in camera_link, view and watch defaulted to base_link:
    following docs/camera.md gave an empty radar."""
    from facing_service.arguments import build_parser

    parser = build_parser()
    frames = {c: parser.parse_args([c]).base_frame for c in ("camera", "watch", "view", "demo")}
    assert set(frames.values()) == {"base_link"}, frames


def test_the_router_offers_no_flag_it_would_ignore():
    """A defect found: router --help offered --exit-without-router (a router waits for none)."""
    from facing_service.arguments import build_parser

    parser = build_parser()
    helped = subprocess.run([sys.executable, "-m", "facing_service", "router", "--help"],
                            capture_output=True, text=True, timeout=30).stdout  # fmt: skip
    assert "--listen" in helped and "--exit-without-router" not in helped
    assert "--exit-without-router" in subprocess.run(
        [sys.executable, "-m", "facing_service", "run", "--help"], capture_output=True, text=True,
        timeout=30).stdout  # fmt: skip
    assert parser.parse_args(["router"]).command == "router"
