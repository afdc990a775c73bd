"""The service on the robots it meets: every rmw_zenoh form (Humble, Jazzy, Kilted, Rolling,
with the attachment and cache designs of older releases) and both zenoh-bridge-ros2dds
generations, through a router, the service started after the robot. The robot and the
subscriptions are ``rmw_zenoh.py``'s, written from those releases' sources."""

from __future__ import annotations

import json
import math
import time

import pytest
from zenoh_ros2_sdk.qos import QosDurability, QosHistoryKind, QosProfile, QosReliability

from facing_service.contract.levels import Level
from facing_service.ros2 import types as ros2_types

import rmw_zenoh
from loopback import endpoint
from rmw_zenoh import Release, Robot, Subscription
from ros_messages import S, ids_list, string, tf_message, transform

pytestmark = pytest.mark.slow  # a router and seconds of streaming per release

TF, IDS, STRING = ros2_types.TF_MESSAGE, ros2_types.IDS_LIST, ros2_types.STRING
LEVEL, INTENT = "hri_msgs/msg/EngagementLevel", "hri_actions_msgs/msg/Intent"

RELEASES = [
    rmw_zenoh.HUMBLE_0_1_1,
    rmw_zenoh.HUMBLE_0_1_9,
    rmw_zenoh.JAZZY_0_2_3,
    rmw_zenoh.JAZZY_0_2_10,
    rmw_zenoh.KILTED_0_6_7,
    rmw_zenoh.ROLLING_0_12_0,
    rmw_zenoh.BRIDGE_1_5_0,
    rmw_zenoh.BRIDGE_1_10_0,
]


def look_at(direction: tuple[float, float, float]) -> tuple[float, float, float, float]:
    """The rotation whose x axis points along ``direction`` (yaw, then pitch; no roll)."""
    dx, dy, dz = direction
    yaw, pitch = math.atan2(dy, dx), -math.atan2(dz, math.hypot(dx, dy))
    cy, sy, cp, sp = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(pitch / 2), math.sin(pitch / 2)
    return (-sy * sp, cy * sp, sy * cp, cy * cp)


def wait_for(predicate, timeout: float = 10.0, what: str = "a condition"):
    deadline = time.monotonic() + timeout
    while not (value := predicate()):
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.05)
    return value


def our_publisher_token(session, topic: str) -> dict:
    """Our publisher of ``topic`` in the ROS graph, as zenoh-ros2-sdk's discovery parses
    rmw_zenoh's liveliness tokens."""
    from zenoh_ros2_sdk.discovery import _parse_liveliness_keyexpr

    tokens = [str(r.ok.key_expr) for r in session.liveliness().get("@ros2_lv/**") if r.ok]
    parsed = [_parse_liveliness_keyexpr(t) for t in tokens]
    (ours,) = [p for p in parsed if p and p["kind"] == "MP" and p["qualified_name"] == topic]
    return ours


@pytest.mark.parametrize("release", RELEASES, ids=str)
def test_every_output_reaches_the_robots_own_subscribers(net, release: Release):
    router = net.router()
    ep = endpoint(router.port)
    session = net.client(ep, mode="client", timestamping=release.bridge)
    robot = Robot(session, release, namespace="bot1")
    try:
        # Before the service exists: the transient-local topics, held in the robot's caches.
        camera = transform("base_link", "camera", 0, (0.1, 0.0, 1.2))
        robot.publish("/tf_static", TF, tf_message(camera), latched=True)
        robot.publish("/humans/persons/tracked", IDS, ids_list(["p1"]), latched=True)
        robot.publish("/humans/persons/p1/face_id", STRING, string("f1"), latched=True)
        time.sleep(0.3)
        fmt = "bridge" if release.bridge else "rmw_zenoh"
        service = net.robot_service(
            ep,
            output="ros2",
            ros_intents=True,
            ros_format=fmt,
            ros_namespace="bot1",
            base_frame="base_link",
        )
        listener = net.client(ep, mode="client")
        subs = {
            topic: Subscription.open(listener, release, topic, typename, ns="bot1")
            for topic, typename in [
                ("/humans/persons/p1/engagement_status", LEVEL),
                ("/intents", INTENT),
                ("/humans/persons/facing", IDS),
            ]
        }
        # f1 is p1's face: one human, said as the person, never as the face
        faces = Subscription.open(listener, release, "/humans/faces/facing", IDS, ns="bot1")
        time.sleep(0.5)  # the subscriptions reach the service's publishers
        # The face 1.5 m ahead of the camera, 0.3 m above it, looking at the robot's origin.
        face_at = (1.5, 0.0, 0.3)
        q = look_at((-0.1 - face_at[0], 0.0, -1.2 - face_at[2]))
        status_topic = "/humans/persons/p1/engagement_status"
        status = subs[status_topic]
        for i in range(150):  # up to 5 s at 30 Hz, as a face tracker streams
            stamp = 10 * S + i * (S // 30)
            robot.publish("/humans/faces/tracked", IDS, ids_list(["f1"], stamp))
            robot.publish("/tf", TF, tf_message(transform("camera", "face_f1", stamp, face_at, q)))
            levels = [ros2_types.deserialize(m.payload, LEVEL).level for m in status.messages()]
            if Level.ENGAGED in levels and subs["/intents"].messages():
                break
            time.sleep(1 / 30)
        wait_for(lambda: subs["/intents"].messages(), what="an intent")
        for topic, sub in subs.items():
            assert sub.messages(), f"{release}: nothing reached {sub.key} ({topic})"
            assert sub.dropped == 0, f"{release}: {sub.dropped} samples on {topic} not parsed"
            numbers = [m.sequence_number for m in sub.messages()]
            if not release.bridge:  # numbered per publisher, no gap; from 1 where the
                # publisher was declared after the subscription (the facing lists were not)
                first = 1 if topic in ("/intents", status_topic) else numbers[0]
                assert numbers == list(range(first, first + len(numbers))), (topic, numbers)
        levels = [ros2_types.deserialize(m.payload, LEVEL).level for m in status.messages()]
        assert Level.ENGAGED in levels, levels
        intent = ros2_types.deserialize(subs["/intents"].messages()[0].payload, INTENT)
        assert (intent.intent, json.loads(intent.data)) == (
            "__intent_engage_with__",
            {"recipient": "p1"},
        )
        facing = [
            ros2_types.deserialize(m.payload, IDS).ids
            for m in subs["/humans/persons/facing"].messages()
        ]
        assert ["p1"] in facing, facing  # ENGAGED, looking straight at the robot: facing
        said_faces = [ros2_types.deserialize(m.payload, IDS).ids for m in faces.messages()]
        assert all("f1" not in ids for ids in said_faces), said_faces
        if not release.bridge:
            publisher = our_publisher_token(listener, "/bot1" + status_topic)
            wanted = rmw_zenoh.TYPE_HASHES[LEVEL] if release.type_hash else "TypeHashNotSupported"
            assert (publisher["type_hash"], publisher["node_name"]) == (wanted, "facing_service")
            qos = QosProfile.decode(publisher["qos"])
            assert (qos.reliability, qos.durability) == (
                QosReliability.RELIABLE,
                QosDurability.VOLATILE,
            )
            assert (qos.history_kind, qos.history_depth) == (QosHistoryKind.KEEP_LAST, 10)
            ros2 = service.status().ros2
            assert ros2 is not None and ros2.form_from.startswith("learned from"), ros2
            assert ros2.distro == ("jazzy" if release.type_hash else "humble"), ros2
            assert ros2.attachment == ("keyed" if release.keyed_attachment else "current")
    finally:
        for sub in [*locals().get("subs", {}).values(), locals().get("faces")]:
            if sub is not None:
                sub.close()
        robot.close()
