"""facing-service replay: a real recording, played by the CLI onto zenoh, read by the
service as it would read the robot."""

from __future__ import annotations

import subprocess
import sys

import pytest

from facing_service.testing import LOOPBACK_FLAGS, running_cli

from loopback import endpoint
from oracles import BAGS

RECORDING = BAGS / "1p_AA_eng_1"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["/no/such/bag"], "BAG '/no/such/bag': no such file or folder"),
        ([str(RECORDING), "--rate", "0"], "argument --rate: must be a number > 0, got 0"),
        ([str(RECORDING), "--rate", "nan"], "argument --rate: must be a number > 0, got nan"),
        pytest.param(  # the bag is read before the setting is checked
            [str(RECORDING), "--ros-domain-id", "-1"],
            "--ros-domain-id=-1: ",
            marks=pytest.mark.shared_data,
        ),
    ],
)
def test_bad_arguments_exit_2_with_one_line(args, message):
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "replay", *args],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 2 and message in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


@pytest.mark.slow
@pytest.mark.shared_data
def test_replay_feeds_the_service_like_the_robot_did(net):
    """Bridge format this time (the evaluation runs rmw_zenoh's): the recording's person
    becomes ENGAGED, and nothing the robot sent is refused."""
    router = net.router()
    ep = endpoint(router.port)
    service = net.robot_service(ep, ros_format="bridge", base_frame="camera_link")
    consumer = net.client(ep, mode="client")
    events = net.recorder(consumer, "hri/events/engagement/camera_link")
    flags = ("--rate", "8", "--ros-format", "bridge", "-m", "client", "-e", ep, *LOOPBACK_FLAGS)
    with running_cli("replay", str(RECORDING), *flags) as proc:
        assert proc.wait(timeout=60) == 0
        output = proc.stdout.read()
    assert "replaying" in output and "sent 918 messages on 8 topics" in output
    events.wait_for(
        lambda i: i.value["body_id"] == "person_rorql" and i.value["level"] == "ENGAGED"
    )
    assert sum(service.status().rejected.values()) == 0


@pytest.mark.slow
@pytest.mark.shared_data
def test_recording_nothing_says_why(net, tmp_path):
    """--record against a service without --output ros2: not 'recorded 0 messages' and
    exit 0, but why, and a failure."""
    router = net.router()
    ep = endpoint(router.port)
    net.robot_service(ep, base_frame="camera_link")  # JSON output only
    out = tmp_path / "run.mcap"
    flags = ("--rate", "8", "--record", str(out), "-m", "client", "-e", ep, *LOOPBACK_FLAGS)
    with running_cli("replay", str(RECORDING), *flags) as proc:
        code = proc.wait(timeout=60)
        output = proc.stdout.read()
    assert code == 1, output
    assert "recorded nothing: no service answered on the robot's topics" in output
    assert "--output ros2" in output
    assert (tmp_path / "run" / "run.mcap").is_file()  # the bag is the folder run/


@pytest.mark.slow
@pytest.mark.shared_data
def test_a_recording_holds_every_topic_the_service_publishes(net, tmp_path):
    """Before: "recorded 280 messages on 4 topics" while a plain subscriber heard the
    groups, the markers and who faces whom too (three of the seven topics published)."""
    import threading

    import zenoh
    from rosbags.rosbag2 import Reader

    from facing_service.ros2.wire import RosFormat, Wire

    router = net.router()
    ep = endpoint(router.port)
    net.robot_service(ep, base_frame="camera_link", output="ros2", ros_intents=True)
    wire = Wire(RosFormat.RMW_ZENOH)  # (the service and the replay default to it)
    heard: dict[str, int] = {}
    lock = threading.Lock()
    listener = net.client(ep, mode="client")

    def count(sample: zenoh.Sample) -> None:
        topic = wire.topic_of(str(sample.key_expr))
        if topic is not None and sample.kind == zenoh.SampleKind.PUT:
            with lock:
                heard[topic] = heard.get(topic, 0) + 1

    every = listener.declare_subscriber("**", count)
    out = tmp_path / "run.mcap"
    flags = ("--rate", "4", "--record", str(out), "-m", "client", "-e", ep, *LOOPBACK_FLAGS)
    with running_cli("replay", str(RECORDING), *flags) as proc:
        assert proc.wait(timeout=90) == 0
    every.undeclare()
    with Reader(tmp_path / "run") as bag:
        recorded: dict[str, int] = {}
        for connection, _, _ in bag.messages():
            recorded[connection.topic] = recorded.get(connection.topic, 0) + 1
    with Reader(RECORDING) as source:
        replayed = {c.topic for c in source.connections}
    published = {t: n for t, n in heard.items() if t not in replayed}
    assert {"/humans/interactions/groups", "/humans/facing/markers"} <= set(published)
    assert set(recorded) == set(published), (recorded, published)
    for topic, n in published.items():  # the subscriber began a moment before, ended after
        assert n - 3 <= recorded[topic] <= n, (topic, recorded[topic], n)
