"""Our ROS 2 publishers on the robot's router, as rmw_zenoh's graph sees them: a node
token, a publisher token per topic, CDR samples on the robot's key, and the
topic's publisher and token gone with its subject."""

from __future__ import annotations

import time

from facing_service.ros2.output import ENGAGEMENT_LEVEL
from facing_service.ros2.wire import FormLearner, Wire
from facing_service.shell.outbox import Kind, Publication
from facing_service.shell.ros_bus import RobotPublishers

from loopback import endpoint, wait_until

TOPIC = "/humans/persons/anna/engagement_status"


def tokens(session) -> list[str]:
    return [str(r.ok.key_expr) for r in session.liveliness().get("@ros2_lv/**") if r.ok]


def test_a_topic_is_declared_with_its_token_numbered_and_undeclared_with_its_subject(net):
    router = net.router()  # the robot's router: ours and the robot are its clients
    ep = endpoint(router.port)
    ours, robot = net.client(ep, mode="client"), net.client(ep, mode="client")
    wire = Wire()
    received = net.recorder(robot, wire.key(TOPIC, ENGAGEMENT_LEVEL))
    publishers = RobotPublishers(ours, wire, "facing_service", FormLearner())
    try:
        wait_until(lambda: publishers.node_token_key() in tokens(robot), 5, "the node")
        time.sleep(0.2)  # the robot's subscriber is known to our session
        for payload in (b"\0\1\0\0" + b"x" * 8, b"\0\1\0\0" + b"y" * 8):
            publishers.send(Publication(TOPIC, payload, Kind.ROS, ENGAGEMENT_LEVEL))
        first, second = received.wait_for(lambda i: True, count=2)
        assert first.payload.endswith(b"x" * 8) and second.payload.endswith(b"y" * 8)
        said = [t for t in tokens(robot) if "/MP/" in t]
        assert len(said) == 1 and "%humans%persons%anna%engagement_status" in said[0]
        publishers.send(Publication(TOPIC, None, Kind.ROS, ENGAGEMENT_LEVEL))  # anna is gone
        wait_until(lambda: not [t for t in tokens(robot) if "/MP/" in t], 5, "no token")
    finally:
        publishers.close()
    wait_until(lambda: not tokens(robot), 5, "the node gone too")
