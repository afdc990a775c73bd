"""REP 155's interaction topics on a robot: two people talking beside the robot,
streamed as a robot streams them (/tf, /humans/bodies/tracked); /humans/interactions/groups
and /humans/interactions/gazing as the robot's own subscriptions receive them
(``rmw_zenoh.Subscription``, written from rmw_zenoh's and the bridge's sources, keys with
the upstream type hashes), decoded by rosbags (an independent CDR implementation)."""

from __future__ import annotations

import time

import pytest

from facing_service.ros2 import types as ros2_types

import rmw_zenoh
from loopback import endpoint
from rmw_zenoh import Release, Robot, Subscription
from ros_messages import S, ids_list, tf_message, transform, yaw_q

pytestmark = pytest.mark.slow  # a router and seconds of streaming per release

TF, IDS = ros2_types.TF_MESSAGE, ros2_types.IDS_LIST
GROUP, GAZE = "hri_msgs/msg/Group", "hri_msgs/msg/Gaze"
MARKERS = "visualization_msgs/msg/MarkerArray"


@pytest.mark.parametrize(
    "release", [rmw_zenoh.HUMBLE_0_1_9, rmw_zenoh.JAZZY_0_2_10, rmw_zenoh.BRIDGE_1_10_0], ids=str
)
def test_two_people_talking_are_a_group_and_face_each_other_on_the_robots_topics(
    net, release: Release
):
    router = net.router()
    ep = endpoint(router.port)
    robot = Robot(net.client(ep, mode="client", timestamping=release.bridge), release)
    try:
        fmt = "bridge" if release.bridge else "rmw_zenoh"
        net.robot_service(
            ep, output="ros2", ros_format=fmt, base_frame="base_link", group_hold_s=0.2
        )
        listener = net.client(ep, mode="client")
        groups = Subscription.open(listener, release, "/humans/interactions/groups", GROUP)
        gazing = Subscription.open(listener, release, "/humans/interactions/gazing", GAZE)
        markers = Subscription.open(listener, release, "/humans/facing/markers", MARKERS)
        time.sleep(0.5)  # the subscriptions reach the service's publishers
        # b1 and b2 2 m ahead of the robot, 1.2 m apart, facing each other
        for i in range(60):  # 2 s at 30 Hz
            stamp = 10 * S + i * (S // 30)
            robot.publish("/humans/bodies/tracked", IDS, ids_list(["b1", "b2"], stamp))
            robot.publish(
                "/tf",
                TF,
                tf_message(
                    transform("base_link", "body_b1", stamp, (2.0, 0.6, 0.0), yaw_q(-90)),
                    transform("base_link", "body_b2", stamp, (2.0, -0.6, 0.0), yaw_q(90)),
                ),
            )
            if groups.messages() and len(gazing.messages()) >= 2:
                break
            time.sleep(1 / 30)
        deadline = time.monotonic() + 5
        while not groups.messages() and time.monotonic() < deadline:
            time.sleep(0.05)
        said = [ros2_types.deserialize(m.payload, GROUP) for m in groups.messages()]
        assert said, f"{release}: no Group on {groups.key}"
        assert all(m.members == ["b1", "b2"] for m in said), [m.members for m in said]
        assert len({m.group_id for m in said}) == 1 and said[0].header.frame_id == "base_link"
        pairs = {
            (g.sender, g.receiver)
            for g in (ros2_types.deserialize(m.payload, GAZE) for m in gazing.messages())
        }
        assert {("b1", "b2"), ("b2", "b1")} <= pairs, pairs
        assert groups.dropped == gazing.dropped == markers.dropped == 0
        # RViz's view of it: both people and their group, as rosbags decodes it
        group_ns = f"group/{said[-1].group_id}"
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            arrays = [ros2_types.deserialize(m.payload, MARKERS) for m in markers.messages()]
            with_group = [a for a in arrays if any(m.ns == group_ns for m in a.markers)]
            if with_group:
                break
            time.sleep(0.05)
        assert with_group, f"{release}: no MarkerArray drew the group"
        drawn = {(m.ns, m.id): m for m in with_group[0].markers}
        assert {ns for ns, _ in drawn} == {"person/body_b1", "person/body_b2", group_ns}
        assert all(m.header.frame_id == "base_link" for m in drawn.values())
        print(f"\n{release}: MarkerArray as rosbags decodes it:")
        for m in with_group[0].markers:  # the closing note quotes it
            print(f"  ns={m.ns!r} id={m.id} type={m.type} action={m.action} "
                  f"points={len(m.points)} text={m.text!r} rgb=({m.color.r:.2f}, "
                  f"{m.color.g:.2f}, {m.color.b:.2f})")  # fmt: skip
        print(f"\n{release}: {said[-1]}\n{sorted(pairs)}")  # the closing note quotes it
    finally:
        robot.close()
