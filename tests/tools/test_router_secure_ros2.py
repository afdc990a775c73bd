"""examples/secure-ros2, tried for real: the robot's router locked down (mutual TLS,
user/password, access control), the real service CLI reading and answering the robot's
own topics with its own identity, a Jazzy robot (tests/rmw_zenoh.py) with its identity,
and a stranger with a valid certificate of its own who may neither publish on /tf or
/humans/* nor read the answers."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from test_router_secure import Deployment, _router_flags

from facing_service.contract.keys import BodyRef
from facing_service.contract.stamps import Time
from facing_service.core.engagement import Level, Zone
from facing_service.core.records import EngagementUpdate
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.input import TOPICS
from facing_service.ros2.output import FACING_TOPICS, engage_intent, engagement_status
from facing_service.testing import running_cli

import rmw_zenoh
from loopback import get, wait_until_answered
from rmw_zenoh import Robot, Subscription
from ros_messages import S, ids_list, string, tf_message, transform
from routers import wait_for_port

pytestmark = pytest.mark.slow  # a router, the service and a robot, as processes and sessions

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "secure-ros2"
ROLES = ("robot", "facing-service", "health")
TF, IDS, STRING = ros2_types.TF_MESSAGE, ros2_types.IDS_LIST, ros2_types.STRING
LEVEL = "hri_msgs/msg/EngagementLevel"
STATUS = "/humans/persons/p1/engagement_status"
JAZZY = rmw_zenoh.JAZZY_0_2_10


@pytest.fixture
def site(tmp_path: Path) -> Iterator[Deployment]:
    site = Deployment(tmp_path / "secure-ros2", EXAMPLE, ROLES, stranger_as="robot")
    with running_cli(*_router_flags(site.port), cwd=site.folder) as router:
        wait_for_port(site.port)
        assert router.poll() is None
        yield site


def person(robot: Robot, person_id: str, face: str, stamp: int) -> None:
    """A face 1.5 m in front of the camera, looking at it, as the robot's tracker says."""
    robot.publish("/humans/faces/tracked", IDS, ids_list([face], stamp))
    look = (0.0, 0.0, 1.0, 0.0)  # x turned back toward the camera
    robot.publish(
        "/tf", TF, tf_message(transform("camera", f"face_{face}", stamp, (1.5, 0, 0), look))
    )


def test_the_robot_and_the_service_work_and_a_stranger_can_do_neither(site):
    robot_session = site.session("robot")
    robot = Robot(robot_session, JAZZY)
    # Transient-local topics before the service exists: held in the robot's caches.
    robot.publish("/tf_static", TF, tf_message(transform("base_link", "camera", 0)), latched=True)
    robot.publish("/humans/persons/tracked", IDS, ids_list(["p1"]), latched=True)
    robot.publish("/humans/persons/p1/face_id", STRING, string("f1"), latched=True)
    stranger_session = site.session("stranger", **site.cert_of("stranger"))
    stranger = Robot(stranger_session, JAZZY)
    health = site.session("health")
    flags = ("-c", "service.json5", "-e", site.endpoint, "--input", "ros2", "--output", "ros2",
             "--base-frame", "base_link", "--instance", "secure")  # fmt: skip
    try:
        with running_cli("run", *flags, cwd=site.folder) as service:
            wait_until_answered(health, "hri/services/facing/*/status", timeout=20)
            answers = Subscription.open(robot_session, JAZZY, STATUS, LEVEL)
            overheard = Subscription.open(stranger_session, JAZZY, STATUS, LEVEL)
            forged_answers = Subscription.open(
                robot_session, JAZZY, "/humans/persons/eve/engagement_status", LEVEL
            )
            time.sleep(0.5)
            for i in range(90):  # 3 s at 30 Hz: the robot's person, and a stranger's
                stamp = 10 * S + i * S // 30
                person(robot, "p1", "f1", stamp)
                stranger.publish("/humans/persons/tracked", IDS, ids_list(["p1", "eve"]))
                stranger.publish("/humans/persons/eve/face_id", STRING, string("e1"))
                person(stranger, "eve", "e1", stamp)
                time.sleep(1 / 30)
            time.sleep(0.5)
            levels = [ros2_types.deserialize(m.payload, LEVEL).level for m in answers.messages()]
            assert Level.ENGAGED in levels, json.dumps(get(health, "hri/services/facing/*/status"))
            assert overheard.messages() == [], "a stranger read the answers"
            assert forged_answers.messages() == [], "a stranger's person got in"
            (status,) = get(health, "hri/services/facing/*/status")
            ros2 = status[1]["ros2"]
            # the stranger's /tf never got in; the robot's node is named by its token
            assert ros2["publishers"]["/tf"] == "/robot; samples from 1 publisher(s)", ros2
            # health passes with its own identity
            env = {
                "FACING_CONFIG": "service.json5",
                "FACING_CONNECT": site.endpoint,
                "FACING_HEALTH_CONFIG": "health.json5",
            }
            healthy = subprocess.run(
                [sys.executable, "-m", "facing_service", "health", "--timeout", "3"],
                env={**os.environ, **env},
                cwd=site.folder,
                capture_output=True,
                text=True,
                timeout=60,
            )
            assert healthy.returncode == 0, healthy.stdout + healthy.stderr
            assert service.poll() is None
    finally:
        robot.close()
        stranger.close()
        for session in (robot_session, stranger_session, health):
            session.close()


def test_the_policy_covers_every_topic_the_service_reads_and_answers_on():
    """A topic added to the service (read or answered) without a rule here would be
    silently denied on a locked-down robot: this fails first. And the robot's own rules
    never let it publish the service's answers, nor the service publish people."""
    acl = json.loads(
        zenoh.Config.from_file(str(EXAMPLE / "router.json5")).get_json("access_control")
    )
    rules = {rule["id"]: rule["key_exprs"] for rule in acl["rules"]}

    def covered(rule: str, key: str) -> bool:
        return any(zenoh.KeyExpr(e).includes(zenoh.KeyExpr(key)) for e in rules[rule])

    read = [
        f"0{topic.replace('*', 'p1')}/{ros2_types.dds_type_name(typename)}/RIHS01_x"
        for topic, typename, _ in TOPICS
    ]
    update = EngagementUpdate(
        BodyRef(frame_id="base_link", body_id="person_p1"), Time.of(1), Level.ENGAGED, 1.0,
        Zone.SOCIAL, Time.of(1), None,
    )  # fmt: skip
    answered = [
        f"0{m.topic}/{ros2_types.dds_type_name(m.typename)}/RIHS01_x"
        for m in (engagement_status(update), engage_intent("p1"))
    ] + [f"0{topic}/hri_msgs::msg::dds_::IdsList_/RIHS01_x" for topic in FACING_TOPICS.values()]
    for key in read:
        for rule in ("robot-publishes", "service-reads", "deliver-people"):
            assert covered(rule, key), (rule, key)
        assert not covered("service-answers", key), key
    for key in answered:
        for rule in ("service-answers", "robot-reads-answers", "deliver-answers"):
            assert covered(rule, key), (rule, key)
        assert not covered("robot-publishes", key), key
