"""The social scene of a base frame (pure): who faces whom, groups with the robot in
them, said on change only, bounded in people and in rate."""

from __future__ import annotations

import math
import random
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from facing_service.contract.stamps import ZERO, Time
from facing_service.core.social.groups import GroupParams, ScaleParams
from facing_service.core.social.memory import MemoryParams
from facing_service.core.social.scene import ROBOT, FrameScene, Person, SceneParams, Scenes

#: The memory off: what is said, and when, from each reading (the memory's own tests:
#: test_memory.py, and the stream ones at the end of this file).
PARAMS = SceneParams(
    GroupParams(),
    ScaleParams(),
    threshold_deg=20.0,
    hysteresis_deg=5.0,
    hold_s=0.3,
    period_s=0.1,
    max_people=4,
    memory=MemoryParams(0.0, 0.0),
)
STREAM = replace(PARAMS, memory=MemoryParams(heading_s=0.5, together_s=4.0))


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
    assert held.groups[0].centre[0] == pytest.approx(3.6, abs=0.01)
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

    class View:  # the worker's TurnSnapshot, as the scenes read it
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
    people["map"] = []  # everyone left: said at once (a loss is no flicker to wait out)
    scenes.touch({"map"})
    (gone,) = scenes.tick(0.5, people_of)
    assert gone.groups == () and gone.dissolved == (held.groups[0].id,)
    assert scenes.current() == [] and scenes.next_due() is None


def test_a_group_dissolving_after_standing_still_is_said_at_its_last_pose_not_its_first():
    """A defect found: the `groups: []` said when people left carried the stamp of the last
    change (their first poses), however long they had stood still since."""
    scene = FrameScene("map", PARAMS)
    people = [person("a", 3.0, 2.0, 0), person("b", 4.2, 2.0, 180)]
    scene.update(people, Time.of(1), 0.0)
    formed = scene.update(people, Time.of(1, 500_000_000), 0.4)
    assert formed is not None and formed.groups and formed.stamp == Time.of(1, 500_000_000)
    for k in range(10):  # standing still for 5 s of pose time: nothing to say
        stamp = Time.of(2 + k // 2, (k % 2) * 500_000_000)
        assert scene.update(people, stamp, 0.5 + 0.1 * k) is None
    gone = scene.update([], ZERO, 2.0)  # both left (a DELETE carries no stamp): said at once
    assert gone is not None and gone.groups == () and gone.dissolved
    assert gone.stamp == Time.of(6, 500_000_000)  # the last pose seen, not (1, 5e8)


def test_a_group_the_robot_is_not_in_says_where_to_join_it_and_follows_its_people():
    """A pair talking 3 m ahead; the robot should stand on their ring, on its
    own side, facing into the group; when they move, the place moves with them (not a
    change of its own: nothing is said until the grouping changes, and a snapshot has it)."""
    scene = FrameScene("map", PARAMS)
    pair = [person("a", 3.0, 0.6, -90), person("b", 3.0, -0.6, 90)]
    scene.update(pair, Time.of(1), 0.0)
    held = scene.update(pair, Time.of(2), 0.4)
    assert held is not None
    (group,) = held.groups
    assert not group.robot and group.join is not None
    assert group.join.x < 3.0 and abs(group.join.y) < 0.3  # the robot's side, between them
    assert abs(math.degrees(group.join.yaw)) < 10  # facing into the group (+x)
    moved = [person("a", 3.5, 0.6, -90), person("b", 3.5, -0.6, 90)]
    assert scene.update(moved, Time.of(3), 0.6) is None
    (now,) = scene.snapshot().groups
    assert now.join is not None and now.join.x == pytest.approx(group.join.x + 0.5, abs=0.05)


def test_the_robot_in_a_group_has_no_place_to_join_it():
    scene = FrameScene("base_link", PARAMS)
    scene.update([person("alice", 1.0, 0.0, 180)], Time.of(1), 0.0)
    held = scene.update([person("alice", 1.0, 0.0, 180)], Time.of(1), 0.4)
    assert held is not None and held.groups[0].robot and held.groups[0].join is None


def test_a_person_engaging_alone_is_greeted_in_front_of_them_facing_them():
    """A person ENGAGING or ENGAGED and in no group: the place 1.2 m in front of them,
    facing them; nobody for a person not engaging, or one in a group, or when someone
    else stands there."""
    scene = FrameScene("map", PARAMS)
    cara = Person("cara", (3.0, 2.0, 0.0), (0.0, 0.0, 1.0, 0.0), engaging=True)  # faces -x
    update = scene.update([cara], Time.of(1), 0.0)
    assert update is not None
    (greeting,) = update.greetings
    assert greeting.body_id == "cara"
    assert (greeting.pose.x, greeting.pose.y) == pytest.approx((1.8, 2.0))
    assert abs(math.degrees(greeting.pose.yaw)) < 1e-6  # facing +x: toward cara
    idle = Person("cara", (3.0, 2.0, 0.0), (0.0, 0.0, 1.0, 0.0), engaging=False)
    gone = scene.update([idle], Time.of(2), 0.2)  # someone to greet who goes is a change
    assert gone is not None and gone.greetings == () and gone.groups_changed
    blocking = person("dan", 1.8, 2.1, 90)  # stands where the robot would
    scene.update([cara, blocking], Time.of(3), 0.4)
    assert scene.snapshot().greetings == ()


def test_a_person_in_a_group_held_with_the_robot_is_not_greeted_while_it_is_said():
    """The group {alice, robot} is said until a new grouping has held; alice,
    turned away but still engaging, is in that group meanwhile and must not be greeted."""
    scene = FrameScene("base_link", PARAMS)
    facing = Person("alice", (1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 0.0), engaging=True)
    scene.update([facing], Time.of(1), 0.0)
    held = scene.update([facing], Time.of(1), 0.4)
    assert held is not None and held.groups[0].members == {ROBOT, "alice"}
    assert held.greetings == ()
    half = math.radians(90) / 2  # turned away: alone in this reading, still engaging
    away = Person("alice", (1.0, 0.0, 0.0), (0.0, 0.0, math.sin(half), math.cos(half)), True)
    update = scene.update([away], Time.of(2), 0.5)
    said = update if update is not None else scene.snapshot()
    assert [g.members for g in said.groups] == [{ROBOT, "alice"}]  # not held long enough
    assert said.greetings == () and scene.snapshot().greetings == ()
    dissolved = scene.update([away], Time.of(3), 0.9)  # the new grouping has held
    assert dissolved is not None and dissolved.groups == ()
    assert [g.body_id for g in dissolved.greetings] == ["alice"]


@pytest.mark.slow
def test_over_a_long_simulated_run_nobody_greeted_is_in_a_group_said_beside():
    """Over five simulated minutes of eight people: every update and every
    read of the scene says each person engaging either in a group or to greet, never both."""
    from facing_service.client.sim import Crowd

    crowd, scene = Crowd(people=8, seed=3), FrameScene("base_link", replace(PARAMS, max_people=8))
    checked = 0
    for tick in range(3000):
        poses = crowd.step(0.1).poses
        rotations = [
            (0.0, 0.0, math.sin(math.radians(p.yaw_deg) / 2), math.cos(math.radians(p.yaw_deg) / 2))
            for p in poses
        ]
        people = [
            Person(p.body_id, (p.x, p.y, 0.0), rotation, engaging=(tick // 7 + i) % 3 != 0)
            for i, (p, rotation) in enumerate(zip(poses, rotations, strict=True))
        ]
        update = scene.update(people, Time.of(tick), tick * 0.1)
        for said in (update, scene.snapshot()):
            if said is None:
                continue
            grouped = {m for g in said.groups for m in g.members}
            assert not grouped & {g.body_id for g in said.greetings}, (tick, said)
            checked += 1
    assert checked > 3000


def test_a_member_who_walks_away_leaves_the_place_the_robot_should_take():
    """A defect found: with one member gone, the pair's two sides look alike and the place was
    the robot's side; the member who just walked away left their place: the join is there,
    facing in, while it stays clear; someone stepping into it takes it back."""
    scene = FrameScene("map", replace(PARAMS, max_people=8))
    trio = [person("a", 3.0, 0.6, -100), person("b", 3.0, -0.6, 100),
            person("c", 4.0, 0.0, 180)]  # c stands on the far side of the pair  # fmt: skip
    scene.update(trio, Time.of(1), 0.0)
    scene.update(trio, Time.of(2), 0.4)
    gone = [*trio[:2], person("c", 8.0, 3.0, 0)]  # c walks off
    scene.update(gone, Time.of(3), 0.5)
    scene.update(gone, Time.of(4), 0.9)
    (pair,) = [g for g in scene.snapshot().groups if g.members == frozenset({"a", "b"})]
    assert pair.join is not None
    assert (pair.join.x, pair.join.y) == pytest.approx((4.0, 0.0), abs=1e-9)  # c's place
    assert abs(math.degrees(math.remainder(pair.join.yaw - math.pi, math.tau))) < 15
    taken = [*gone, person("d", 4.1, 0.1, 180)]  # someone else steps in
    scene.update(taken, Time.of(5), 1.0)
    (pair,) = [g for g in scene.snapshot().groups if {"a", "b"} <= g.members]
    assert pair.join is None or math.hypot(pair.join.x - 4.0, pair.join.y) > 0.3


def test_with_the_memory_a_pair_is_said_once_the_last_seconds_show_it():
    """Back to back for 5 s, then face to face: their headings turn (0.35 s to cross),
    half the memory (2 s) of being together, the hold (0.3 s). They stand still after
    the turn, and the scene is looked at again until its memory settles."""
    scenes = Scenes(STREAM)
    apart = [person("a", 3.0, 2.0, 180), person("b", 4.2, 2.0, 0)]
    facing = [person("a", 3.0, 2.0, 0), person("b", 4.2, 2.0, 180)]
    now = 0.0

    class Snapshot:
        def people(self, frame_id):
            return (apart if now < 5.0 else facing), Time.of(1)

    formed_at, calls = None, []
    for k in range(150):
        now = k * 0.1
        if k in (0, 50):
            scenes.touch({"map"})  # the tracker's news: a pose changed
        if scenes.next_due() is not None:
            calls.append(now)
        for update in scenes.tick(now, Snapshot()):
            if update.groups and formed_at is None:
                formed_at = now
    assert formed_at is not None and formed_at - 5.0 == pytest.approx(2.65, abs=0.25)
    assert sum(c >= 5.0 for c in calls) > 20  # still people, looked at while settling
    assert scenes.next_due() is None  # ... and no more once it has


def test_with_the_memory_a_heading_flickering_for_one_reading_moves_no_group():
    scene = FrameScene("map", STREAM)
    pair = [person("a", 3.0, 2.0, 0), person("b", 4.2, 2.0, 180)]
    said = None
    for k in range(100):
        turned = k == 60  # one reading: a looks away
        people = [person("a", 3.0, 2.0, 90 if turned else 0), pair[1]]
        said = scene.update(people, Time.of(1 + k), k * 0.1) or said
        if k > 40:
            assert [sorted(g.members) for g in scene.tracker.groups.values()] == [["a", "b"]]
    assert said is not None


def test_a_participant_looks_with_their_face_and_stands_with_their_body():
    """Where a person has both, the face says who they look at and the body how
    they stand. a and b stand face to face (a group); a's face turns to the robot: a faces
    the robot, not b, and the group holds (bodies did not move)."""
    scene = FrameScene("map", PARAMS)
    a_body = person("a", 3.0, 2.0, 0)
    toward_robot = person("a", 3.0, 2.0, math.degrees(math.atan2(-2.0, -3.0)))
    a = replace(a_body, look=(toward_robot.translation, toward_robot.rotation))
    b = person("b", 4.2, 2.0, 180)
    scene.update([a, b], Time.of(1), 0.0)
    held = scene.update([a, b], Time.of(2), 0.35)
    assert held is not None and [sorted(g.members) for g in held.groups] == [["a", "b"]]
    assert ("a", ROBOT) in held.gazing and ("a", "b") not in held.gazing
    assert ("b", "a") in held.gazing  # b looks at a, wherever a looks


def test_a_turned_face_alone_is_said_though_nobody_moved_where_they_stand():
    """The scene is worked out again when only where someone looks changed."""
    scene = FrameScene("map", PARAMS)
    b = person("b", 4.2, 2.0, 180)
    a = person("a", 3.0, 2.0, 0)
    scene.update([a, b], Time.of(1), 0.0)
    scene.update([a, b], Time.of(2), 0.35)
    away = person("a", 3.0, 2.0, 90)
    turned = scene.update([replace(a, look=(away.translation, away.rotation)), b], Time.of(3), 0.5)
    assert turned is not None and ("a", "b") not in turned.gazing


@pytest.mark.parametrize("seed", range(6))
def test_the_groups_said_do_not_depend_on_what_people_are_called(seed):
    """A room's people heard in another order and named so that their ids sort
    the other way are grouped alike, at first sight and over a stream of turning heads."""
    rng = random.Random(seed)
    spots = rng.sample([(x, y) for x in range(-6, 7) for y in range(-6, 7)], 10)
    frames = [[rng.choice((0, 90, 180, 270)) for _ in spots] for _ in range(8)]
    said = []
    for names in ([f"p{k:02d}" for k in range(10)], [f"q{99 - k:02d}" for k in range(10)]):
        order = list(range(10)) if names[0] == "p00" else rng.sample(range(10), 10)
        scene = FrameScene("base_link", replace(STREAM, max_people=20))
        seen = []
        for k, headings in enumerate(frames):
            people = [person(names[i], 0.4 * spots[i][0], 0.4 * spots[i][1], headings[i])
                      for i in order]  # fmt: skip
            for tick in range(20):  # each frame held 2 s at 10 Hz
                scene.update(people, Time.of(20 * k + tick), 2.0 * k + 0.1 * tick)
            seen.append({frozenset(names.index(m) for m in g.members if m != ROBOT)
                         for g in scene.tracker.groups.values()})  # fmt: skip
        said.append(seen)
    assert said[0] == said[1]


def test_a_member_lost_leaves_the_group_said_at_once_and_the_group_keeps_its_id():
    """Someone the service has said gone is in no group said after: a trio that loses a
    member is said a pair at once, under its id (not after the hold: a loss is no
    flicker), with the place the member left to join it; the pair losing one more is
    said dissolved at once."""
    scene = FrameScene("map", STREAM)
    trio = [person("a", 2.0, 0.0, 90), person("b", 2.0, 1.2, -90), person("c", 2.6, 0.6, 180)]
    for k in range(30):
        scene.update(trio, Time.of(1 + k), 0.1 * k)
    (group,) = scene.snapshot().groups
    assert group.members == frozenset("abc")
    lost_c = scene.update(trio[:2], Time.of(40), 3.0)
    assert lost_c is not None and [(g.id, g.members) for g in lost_c.groups] == [
        (group.id, frozenset("ab"))
    ]
    (pair,) = lost_c.groups  # the place c stood in is where to join them
    assert pair.join is not None and (pair.join.x, pair.join.y) == pytest.approx((2.6, 0.6))
    lost_b = scene.update(trio[:1], Time.of(41), 3.1)
    assert lost_b is not None and lost_b.groups == () and lost_b.dissolved == (group.id,)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.sampled_from("abcdef"), st.integers(1, 8)), min_size=1, max_size=25))
def test_over_any_comings_and_goings_no_group_said_holds_someone_gone(steps):
    """Sequences of what a tracker sends: people of a room (two conversations and a
    passer-by) lost and back in any order, time going on between. Against the simplest
    model of who is there (the people given to the last update), every update and every
    read says groups only of them and the robot."""
    room = [person("a", 2.0, 0.0, 90), person("b", 2.0, 1.2, -90), person("c", 2.6, 0.6, 180),
            person("d", 5.0, 3.0, 0), person("e", 6.2, 3.0, 180),
            person("f", 4.0, -2.0, 45)]  # fmt: skip
    scene = FrameScene("map", replace(STREAM, max_people=8))
    here, now = set("abcdef"), 0.0
    for name, ticks in steps:
        here ^= {name}  # lost, or back
        for _ in range(ticks):
            now += 0.1
            update = scene.update([p for p in room if p.id in here], Time.from_seconds(now), now)
            for said in (update, scene.snapshot()):
                for g in said.groups if said is not None else ():
                    assert g.members <= here | {ROBOT}, (now, sorted(here), g)
