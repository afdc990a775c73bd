"""The social scene of a base frame (pure): who faces whom, groups with the robot in
them, said on change only, bounded in people and in rate."""

from __future__ import annotations

import math

from facing_service.contract.stamps import ZERO, Time
from facing_service.core.groups import GroupParams, ScaleParams
from facing_service.core.scene import ROBOT, FrameScene, Person, SceneParams, Scenes

PARAMS = SceneParams(
    GroupParams(),
    ScaleParams(),
    threshold_deg=20.0,
    hysteresis_deg=5.0,
    hold_s=0.3,
    period_s=0.1,
    max_people=4,
)


def person(name: str, x: float, y: float, heading_deg: float) -> Person:
    half = math.radians(heading_deg) / 2
    return Person(name, (x, y, 0.0), (0.0, 0.0, math.sin(half), math.cos(half)))


def test_two_people_talking_face_each_other_and_form_a_group_once_it_has_held():
    scene = FrameScene("map", PARAMS)
    people = [person("a", 3.0, 2.0, 0), person("b", 4.2, 2.0, 180)]
    first = scene.update(people, Time.of(1), 0.0)
    assert first is not None and first.gazing == {("a", "b"), ("b", "a")}
    assert first.groups == ()  # not held yet: said once with the pairs, no group
    assert scene.pending and scene.update(people, Time.of(1), 0.1) is None
    held = scene.update(people, Time.of(2), 0.35)
    assert held is not None and [sorted(g.members) for g in held.groups] == [["a", "b"]]
    assert held.changed == held.groups and not held.groups[0].robot
    assert held.groups[0].centre[0] == __import__("pytest").approx(3.6, abs=0.01)
    assert scene.update(people, Time.of(3), 0.5) is None  # nothing changed: nothing said


def test_a_person_facing_the_robot_is_in_a_group_with_it_and_the_robot_faces_them():
    scene = FrameScene("base_link", PARAMS)
    update = scene.update([person("alice", 1.0, 0.0, 180)], Time.of(1), 0.0)
    assert update is not None and update.gazing == {("alice", ROBOT), (ROBOT, "alice")}
    held = scene.update([person("alice", 1.0, 0.0, 180)], Time.of(1), 0.4)
    assert held is not None and held.groups[0].robot
    assert held.groups[0].members == {ROBOT, "alice"}


def test_who_faces_whom_keeps_a_pair_within_the_hysteresis():
    scene = FrameScene("map", PARAMS)
    # b is 10 deg off a's heading: a faces b
    a, b_at = person("a", 0.0, 5.0, 0), (5.0, 5.0 + 5.0 * math.tan(math.radians(10)))
    scene.update([a, person("b", *b_at, 90)], Time.of(1), 0.0)
    assert ("a", "b") in scene.gazing
    # 22 deg: beyond the cone (20) but within the hysteresis (25): still facing
    b_at = (5.0, 5.0 + 5.0 * math.tan(math.radians(22)))
    scene.update([a, person("b", *b_at, 90)], Time.of(2), 0.1)
    assert ("a", "b") in scene.gazing
    b_at = (5.0, 5.0 + 5.0 * math.tan(math.radians(27)))
    scene.update([a, person("b", *b_at, 90)], Time.of(3), 0.2)
    assert ("a", "b") not in scene.gazing


def test_a_crowd_is_cut_to_the_nearest_and_the_rest_counted():
    scene = FrameScene("map", PARAMS)
    crowd = [person(f"p{i}", 2.0 + i, 0.0, 90) for i in range(7)]
    update = scene.update(crowd, Time.of(1), 0.0)
    assert update is not None and update.left_out == 3
    assert {p for pair in update.gazing for p in pair} <= {"p0", "p1", "p2", "p3", ROBOT}


def test_scenes_work_a_frame_out_at_most_once_a_period_and_forget_it_when_empty():
    scenes = Scenes(PARAMS)
    people = {"map": [person("a", 3.0, 2.0, 0), person("b", 4.2, 2.0, 180)]}
    calls = []

    class View:  # the worker's TurnView, as the scenes read it
        def people(self, frame: str):
            calls.append(frame)
            return people.get(frame, []), Time.of(1)

    people_of = View()

    assert scenes.next_due() is None
    scenes.touch({"map"})
    assert scenes.next_due() == float("-inf")
    assert [u.frame_id for u in scenes.tick(0.0, people_of)] == ["map"]
    scenes.touch({"map"})
    assert scenes.tick(0.05, people_of) == [] and calls == ["map"]  # within the period
    assert scenes.next_due() == 0.1
    (held,) = scenes.tick(0.4, people_of)  # the grouping has held: said
    assert [sorted(g.members) for g in held.groups] == [["a", "b"]]
    assert [u.groups for u in scenes.current()] == [held.groups]
    people["map"] = []  # everyone left
    scenes.touch({"map"})
    scenes.tick(0.5, people_of)
    (gone,) = scenes.tick(0.9, people_of)
    assert gone.groups == () and gone.dissolved == (held.groups[0].id,)
    assert scenes.current() == [] and scenes.next_due() is None


def test_a_group_dissolving_after_standing_still_is_said_at_its_last_pose_not_its_first():
    """Issue 46: the `groups: []` said when people left carried the stamp of the last
    change (their first poses), however long they had stood still since."""
    scene = FrameScene("map", PARAMS)
    people = [person("a", 3.0, 2.0, 0), person("b", 4.2, 2.0, 180)]
    scene.update(people, Time.of(1), 0.0)
    formed = scene.update(people, Time.of(1, 500_000_000), 0.4)
    assert formed is not None and formed.groups and formed.stamp == Time.of(1, 500_000_000)
    for k in range(10):  # standing still for 5 s of pose time: nothing to say
        stamp = Time.of(2 + k // 2, (k % 2) * 500_000_000)
        assert scene.update(people, stamp, 0.5 + 0.1 * k) is None
    scene.update([], ZERO, 2.0)  # both left (a DELETE carries no stamp)
    gone = scene.update([], ZERO, 2.4)
    assert gone is not None and gone.groups == () and gone.dissolved
    assert gone.stamp == Time.of(6, 500_000_000)  # the last pose seen, not (1, 5e8)
