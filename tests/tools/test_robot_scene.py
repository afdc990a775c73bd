"""The simulated ROS4HRI robot, read as the service reads a robot (its topics decoded and
routed into ``People``, pure): one human is one participant at every moment, the poses
composed through its camera's optical frame land where the crowd put each person, and
anonymous persons are recognised as known ones."""

from __future__ import annotations

import math

import pytest

from facing_service.client.sim import Crowd
from facing_service.contract.stamps import NS_PER_S as S
from facing_service.ros2.input import RosSample, route
from facing_service.ros2.people import People, Update
from facing_service.ros2.wire import Wire
from facing_service.tools.robot_scene import (
    BODY_HEIGHT_M,
    KNOWN_NAMES,
    RobotMessage,
    RobotScene,
)

WIRE = Wire()
RATE_HZ = 30.0


def apply(people: People, messages: list[RobotMessage]) -> list[Update]:
    updates = []
    for message in messages:
        sample = RosSample(WIRE.key(message.topic, message.typename), message.cdr)
        update = route(people, WIRE, sample)
        assert isinstance(update, Update), update  # nothing the robot sends is refused
        assert update.refused == []
        updates.append(update)
    return updates


def human_of(subject: str, known: dict[str, str]) -> str:
    """The crowd's id of the human a subject stands for (body_b7, person_anonymous_person_f7
    and the person it is recognised as are all p7)."""
    kind, _, rest = subject.partition("_")
    if kind == "body":
        return "p" + rest.removeprefix("b")
    assert kind == "person", subject  # a face is always some person's: never its own
    if rest.startswith("anonymous_person_f"):
        return "p" + rest.removeprefix("anonymous_person_f")
    return known[rest]


@pytest.mark.parametrize(("seed", "late"), [(0, 0), (1, 0), (2, 0), (0, 2), (1, 3), (2, 5)])
def test_every_human_is_one_participant_at_every_moment(seed: int, late: int):
    """In order, and with the person topics ``late`` ticks behind the others (they come
    through other subscriptions: 2 to 5 ticks, 67 to 167 ms), which the service's wait
    for a person manager (``--ros-join-wait-s``, 0.25 s) covers."""
    scene = RobotScene(Crowd(people=6, seed=seed))
    people = People("base_link", join_wait_ns=S // 4 if late else 0)
    behind: list[list[RobotMessage]] = [[] for _ in range(late)]
    present: set[str] = set()
    known: dict[str, str] = {}
    named_from: dict[str, str] = {}  # known person -> the anonymous person it was
    apply(people, scene.start())
    for _ in range(int(90 * RATE_HZ)):
        messages = scene.step(1 / RATE_HZ)
        if late:
            behind.append([m for m in messages if m.topic.startswith("/humans/persons/")])
            messages = [m for m in messages if not m.topic.startswith("/humans/persons/")]
            messages += behind.pop(0)
        for person, human in scene.persons().items():
            if person in KNOWN_NAMES:
                known.setdefault(person, human)
        for update in apply(people, messages):
            present |= {p.body_id for p in update.poses}
            present -= set(update.lost)
            humans = [human_of(subject, known) for subject in present]
            assert len(humans) == len(set(humans)), sorted(present)
        for subject in present:
            if subject.removeprefix("person_") in KNOWN_NAMES:
                name = subject.removeprefix("person_")
                named_from.setdefault(name, f"person_anonymous_person_f{known[name][1:]}")
    apply(people, [m for held in behind for m in held] + scene.stop())
    # every name was given, each to a human first seen as an anonymous person
    assert sorted(named_from) == sorted(KNOWN_NAMES)
    assert people.subjects() == []


def test_a_known_person_looks_from_its_face_and_stands_in_its_body():
    """ada links her face and her body: she looks from the face while it is seen (facing,
    engagement), stands in the body (groups, where to stand), and is one participant."""
    scene = RobotScene(Crowd(people=5, seed=0))
    people = People("base_link")
    apply(people, scene.start())
    seen = set()
    for _ in range(int(30 * RATE_HZ)):
        apply(people, scene.step(1 / RATE_HZ))
        participant = people.presence.participants.get("person_ada")
        if participant is not None:
            number = scene.persons()["ada"][1:]
            body, face = f"body_b{number}", f"face_f{number}"
            assert participant.looks in ((face, body), (body,))
            assert participant.stands == (body if participant.looks[0] == face else None)
            seen.add(participant.looks)
    assert len(seen) == 2  # both: her face seen and not


def test_poses_composed_through_the_camera_land_where_the_crowd_put_each_person():
    """The bodies are published in the camera's optical frame; the service's lookup in
    base_link gives back the crowd's own pose (a twin crowd, same seed, says where)."""
    scene, twin = RobotScene(Crowd(people=5, seed=3)), Crowd(people=5, seed=3)
    people = People("base_link")
    apply(people, scene.start())
    checked = 0
    for _ in range(int(10 * RATE_HZ)):
        truth = {f"body_b{p.body_id[1:]}": p for p in twin.step(1 / RATE_HZ).poses}
        for update in apply(people, scene.step(1 / RATE_HZ)):
            for sample in update.poses:
                if sample.body_id not in truth or sample.pose.stamp != twin_stamp(twin):
                    continue
                where = truth[sample.body_id]
                t, q = sample.pose.translation, sample.pose.rotation
                assert t == pytest.approx((where.x, where.y, BODY_HEIGHT_M), abs=1e-9)
                yaw = math.degrees(2 * math.atan2(q[2], q[3]))
                assert abs(q[0]) < 1e-9 and abs(q[1]) < 1e-9
                assert (yaw - where.yaw_deg + 180) % 360 - 180 == pytest.approx(0, abs=1e-6)
                checked += 1
    assert checked > 300  # the bodies no person holds, 10 s of them


def twin_stamp(crowd: Crowd) -> int:
    return round((crowd.start_s + crowd.now) * 1e9)
