"""A buggy or hostile robot beside a real person: what it sends is refused and counted,
the person's results go on, and the status tells the truth."""

from __future__ import annotations

import time

import pytest

from facing_service import ros2_types
from facing_service.client import FacingClient
from facing_service.loopback import loopback_config

import rmw_zenoh
from loopback import endpoint
from rmw_zenoh import Robot
from ros_messages import S, ids_list, tf_message, transform, yaw_q

pytestmark = pytest.mark.slow  # a router and seconds of streaming

TF, IDS = ros2_types.TF_MESSAGE, ros2_types.IDS_LIST


@pytest.fixture
def robot_and_service(net):
    router = net.router()
    ep = endpoint(router.port)
    service = net.robot_service(ep, base_frame="base_link")
    robot = Robot(net.client(ep, mode="client"), rmw_zenoh.JAZZY_0_2_10)
    consumer = net.client(ep, mode="client")
    time.sleep(0.3)
    yield ep, service, robot, consumer
    robot.close()


def person_then(robot: Robot, bad: bytes, seconds: float = 1.0) -> None:
    """A real person (body_a, 2 m ahead, facing) streamed at 30 Hz, ``bad`` sent halfway."""
    robot.publish("/humans/bodies/tracked", IDS, ids_list(["a"]))
    for i in range(int(seconds * 30)):
        body = transform("base_link", "body_a", 10 * S + i * S // 30, (2.0, 0.0, 0.0), yaw_q(180))
        robot.publish("/tf", TF, tf_message(body))
        if i == int(seconds * 15):
            robot.publish("/tf", TF, bad)
        time.sleep(1 / 30)


def poisoned(sec: int, nanosec: int, t=(1.0, 0.0, 0.0)) -> bytes:
    message = ros2_types.message_type(TF)(transforms=[transform("base_link", "ghost", 0, t)])
    message.transforms[0].header.stamp.sec = sec
    message.transforms[0].header.stamp.nanosec = nanosec
    return ros2_types.serialize(message, TF)


def test_one_uninitialised_stamp_poisons_nothing(net, robot_and_service):
    """It used to become a frame's newest stamp; every later batch then raised while
    building the aggregate: no DELETE for people who left, no aggregate, status 'ok'."""
    _, service, robot, consumer = robot_and_service
    frames = net.recorder(consumer, "hri/facing/base_link")
    results = net.recorder(consumer, "hri/bodies/body_a/facing/base_link")
    person_then(robot, poisoned(2**31 - 1, 2**32 - 1))
    robot.publish("/humans/bodies/tracked", IDS, ids_list([]))  # the person leaves
    results.wait_for(lambda i: i.kind == "delete")
    frames.wait_for(lambda i: i.value["bodies_tracked"] == [])
    status = service.status()
    assert status.status == "ok" and status.counters["worker_errors"] == 0
    assert status.rejected["tf_invalid_stamp"] == 1
    assert sum(i.kind == "put" for i in results.items) == 30  # every pose of the person


def test_a_huge_translation_never_reaches_an_output(net, robot_and_service):
    """1.7e308 m used to publish inf/NaN distances: invalid JSON that FacingClient could
    not read for the whole frame."""
    ep, service, robot, _ = robot_and_service
    person_then(robot, tf_message(transform("base_link", "body_a", 10 * S + 1, (1.7e308, 0, 0))))
    config = loopback_config(connect=[ep], mode="client")
    with FacingClient("hri", "base_link", session_config=config) as client:
        (state,) = client.query("base_link")
    assert state.body_id == "body_a" and state.distance_m == pytest.approx(2.0)
    assert service.status().rejected["tf_out_of_range"] == 1


def test_a_worker_error_turns_the_status_degraded_until_a_batch_succeeds(
    net, robot_and_service, monkeypatch
):
    _, service, robot, _ = robot_and_service
    ingest, raised = service._tracker.ingest, []

    def once_broken(*args, **kwargs):
        if not raised:
            raised.append(True)
            raise RuntimeError("a bug in one batch")
        return ingest(*args, **kwargs)

    monkeypatch.setattr(service._tracker, "ingest", once_broken)
    robot.publish("/humans/bodies/tracked", IDS, ids_list(["a"]))
    body = transform("base_link", "body_a", 10 * S, (2.0, 0.0, 0.0), yaw_q(180))
    robot.publish("/tf", TF, tf_message(body))
    deadline = time.monotonic() + 5
    while (status := service.status()).counters["worker_errors"] == 0:
        assert time.monotonic() < deadline
        time.sleep(0.02)
    assert status.status == "degraded"
    robot.publish("/tf", TF, tf_message(transform("base_link", "body_a", 11 * S, (2.0, 0, 0))))
    while service.status().status != "ok":
        assert time.monotonic() < deadline + 5
        time.sleep(0.02)


def test_an_oversized_message_is_refused_undecoded(net, robot_and_service):
    """One 104 MB TFMessage peaked at 2.2 GB: a message over --ros-max-message-bytes
    (1 MiB) is refused before it is copied or decoded, beside a person who goes on."""
    _, service, robot, consumer = robot_and_service
    results = net.recorder(consumer, "hri/bodies/body_a/facing/base_link")
    many = [transform("base_link", f"f{i}", 10 * S, (1.0, 0.0, 0.0)) for i in range(20_000)]
    huge = tf_message(*many)
    assert len(huge) > 1 << 20
    person_then(robot, huge)
    deadline = time.monotonic() + 5
    while sum(i.kind == "put" for i in results.items) < 30:
        assert time.monotonic() < deadline, "the person's results stopped"
        time.sleep(0.02)
    status = service.status()
    assert status.rejected["payload_too_large"] == 1 and status.status == "ok"
    assert not service._people.tf.has_frame("f0")
