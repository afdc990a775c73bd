"""The ROS 2 path tried with nothing else: a simulated ROS4HRI robot published by
``simulate --ros2`` and ``demo --ros2``, recorded as a bag (read back by rosbags), and that
bag replayed into a service that reads it as it would read a robot."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from facing_service.testing import LOOPBACK_FLAGS, running_cli

from loopback import endpoint


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["simulate", "--record", "x.mcap", *LOOPBACK_FLAGS], "--record only with --ros2"),
        (["demo", "--record", "x.mcap"], "--record only with --ros2"),
        (["demo", "--ros2", "--camera"], "--ros2 or --camera"),
        (["simulate", "--ros2", "--record", "/no/such/dir/x.mcap"], "no such folder"),
        (["simulate", "--ros2", "--ros-domain-id", "-1", *LOOPBACK_FLAGS], "--ros-domain-id=-1"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(args, message):
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", *args],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 2 and message in proc.stderr, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr


@pytest.mark.slow
def test_a_simulated_robot_recorded_then_replayed_into_a_service(net, tmp_path):
    """Recorded with nothing else running (a recording needs no service), played again by
    ``replay`` into a service: the recognised person is one participant, its face and
    body never results of their own, and nothing the robot sent is refused."""
    from rosbags.interfaces import QosDurability
    from rosbags.rosbag2 import Reader

    out = tmp_path / "robot.mcap"
    flags = ("--duration-s", "8", "--record", str(out), *LOOPBACK_FLAGS)
    with running_cli("simulate", "--ros2", *flags) as proc:
        assert proc.wait(timeout=60) == 0
        output = proc.stdout.read()
    assert re.search(r"recorded \d+ messages on \d+ topics to .*robot", output), output
    with Reader(tmp_path / "robot") as bag:
        topics = {c.topic: c for c in bag.connections}
    assert {"/tf", "/tf_static", "/humans/persons/tracked", "/humans/faces/tracked",
            "/humans/bodies/tracked", "/humans/persons/ada/face_id",
            "/humans/persons/ada/body_id"} <= set(topics)  # fmt: skip
    latched = topics["/tf_static"].ext.offered_qos_profiles
    assert [q.durability for q in latched] == [QosDurability.TRANSIENT_LOCAL]

    router = net.router()
    ep = endpoint(router.port)
    service = net.robot_service(ep, base_frame="base_link")
    results = net.recorder(net.client(ep, mode="client"), "hri/bodies/*/facing/base_link")
    replay = ("--rate", "2", "-m", "client", "-e", ep, *LOOPBACK_FLAGS)
    with running_cli("replay", str(tmp_path / "robot"), *replay) as proc:
        assert proc.wait(timeout=60) == 0
    results.wait_for(lambda item: item.key.split("/")[2] == "person_ada")
    subjects = {item.key.split("/")[2] for item in results.items}
    assert not [s for s in subjects if s.startswith("face_")], subjects
    assert sum(service.status().rejected.values()) == 0


@pytest.mark.slow
def test_the_ros2_demo_runs_alone_with_a_recognised_person_said_once():
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "demo", "--ros2", "--duration-s", "8",
         "--view-port", "0"],
        capture_output=True,
        text=True,
        timeout=90,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr
    assert "a simulated ROS 2 robot running ROS4HRI publishes its people" in proc.stdout
    rows = re.findall(r"│ (\S+)\s*│\s*(?:yes|no)\s*│", proc.stdout)
    assert "person_ada" in rows, proc.stdout[-3000:]
    assert not [r for r in rows if r.startswith("face_")]
    assert re.search(r"the robot published \d+ messages on \d+ topics", proc.stdout)
    assert proc.stderr == ""
