"""The ROS 2 input as the worker knows it: how it names where a pose came from, what it
says at start and in the status, and the memory it holds of invented ids."""

from __future__ import annotations

import time

import pytest

from facing_service.config.settings import Settings
from facing_service.contract.keys import BodyRef
from facing_service.contract.poses import Pose
from facing_service.contract.stamps import Time
from facing_service.core.records import PoseSample
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.input import RosSample
from facing_service.ros2.wire import Wire
from facing_service.shell.compose import robot_for, robot_reading
from facing_service.shell.ledger import Ledger
from facing_service.shell.ros_input import RosInput

from memory import rss_mb
from ros_messages import string


def ros_input(**given) -> RosInput:
    settings = Settings(input="ros2", base_frame="base_link", **given)
    return RosInput(
        robot_reading(settings), robot_for(settings, False), Ledger(time.monotonic), time.monotonic
    )


def test_it_says_what_it_reads_and_where_a_pose_came_from():
    source = ros_input(ros_namespace="robot1")
    line = source.start_line()
    assert "ROS 2 input in rmw_zenoh format (domain 0, namespace 'robot1')" in line
    assert "people looked up in base_link" in line
    pose = Pose(Time.of(1), (1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    body = PoseSample(BodyRef(frame_id="base_link", body_id="body_b1"), pose)
    assert source.origin(body) == "/tf base_link -> body_b1 (body_b1)"  # REP 155's frame
    person = PoseSample(BodyRef(frame_id="base_link", body_id="person_p1"), pose)
    assert source.origin(person) == "/tf base_link -> ? (person_p1)"  # no face or body yet
    status = source.status()
    assert (status.format, status.distro, status.tf_clears) == ("rmw_zenoh", "jazzy", 0)


@pytest.mark.slow
def test_300_000_invented_person_ids_cost_under_15_mb():
    """Every /humans/persons/<id>/body_id topic used to be counted by name, forever:
    300 000 invented ids held 60 MB. Topics are counted by pattern, links are bounded."""

    robot = ros_input()
    wire, payload = Wire(), string("f1")
    keys = [wire.key(f"/humans/persons/p{i}/body_id", ros2_types.STRING) for i in range(300_000)]
    before = rss_mb()
    for key in keys:
        robot.route(RosSample(key, payload))
    grown = (rss_mb() - before) * 2**20 / 1e6  # MiB -> MB
    print(f"\n300 000 invented person ids: +{grown:.1f} MB")
    assert grown <= 15, grown
