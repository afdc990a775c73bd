"""F-formations from positions and headings (pure): who stands in one conversation."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from facing_service.core.social.groups import (
    GroupParams,
    RoomScale,
    ScaleParams,
    detect,
    detect_centres,
    groups,
    on_the_ring,
)

P = GroupParams()


def gcff_params(stride: float, mdl: float) -> GroupParams:
    """GCFF's own rule in our parameters: one fixed stride for everyone, no cone."""
    return GroupParams(stride_k=0.0, stride_min=stride, stride_max=stride, cone_deg=0.0, mdl=mdl)


def scene(*people: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """People as (x, y, heading in degrees)."""
    array = np.array(people, dtype=np.float64)
    return array[:, :2], np.radians(array[:, 2])


def test_two_people_facing_each_other_are_a_group_and_back_to_back_are_not():
    assert groups(detect(*scene((0, 0, 0), (1.0, 0, 180)), P)) == [[0, 1]]
    assert groups(detect(*scene((0, 0, 180), (1.0, 0, 0)), P)) == []


def test_a_ring_of_five_is_one_group_and_a_passer_by_is_not_in_it():
    ring = [
        (math.cos(a), math.sin(a), math.degrees(a) + 180)
        for a in np.linspace(0, 2 * math.pi, 5, endpoint=False)
    ]
    labels = detect(*scene(*[(0.6 * x, 0.6 * y, h) for x, y, h in ring], (3.0, 3.0, 90)), P)
    assert groups(labels) == [[0, 1, 2, 3, 4]]


def test_two_conversations_side_by_side_are_two_groups():
    pairs = scene((0, 0, 0), (1.0, 0, 180), (0, 2.0, 0), (1.0, 2.0, 180))
    assert sorted(groups(detect(*pairs, P))) == [[0, 1], [2, 3]]


def test_the_robot_is_a_participant_like_any_other():
    """The robot at the origin facing +x, a person 1 m ahead facing it: a group of two;
    turned away 2.5 m ahead, no group. (Within about 2.2 m, a back turned to the robot
    joins its o-space in the method alone: it knows positions and headings, not who
    talks, and the default that holds on GDet's 90-degree headings is lenient; the scene
    keeps the robot to its ring, next test.)"""
    assert groups(detect(*scene((0, 0, 0), (1.0, 0, 180)), P)) == [[0, 1]]
    assert groups(detect(*scene((0, 0, 0), (2.5, 0, 0)), P)) == []


@pytest.mark.parametrize(
    ("people", "with_robot"),
    [
        ([(1.0, 0, 180)], True),  # 1 m ahead, facing the robot: a conversation
        ([(2.2, -1.0, 155)], False),  # 2.4 m away, facing it: engaging, not a group
        ([(1.5, 0, 0)], False),  # 1.5 m ahead, back turned
        ([(2.0, 0.6, -90), (2.0, -0.6, 90)], False),  # a pair the robot merely watches
        ([(0.8, 0.5, -150), (0.8, -0.5, 150)], True),  # two people facing the robot, close
    ],
)
def test_the_robot_is_in_a_group_only_on_its_ring(people, with_robot):
    """A lenient default once let the robot into a conversation it faced from 2 m
    (tests/ros2/test_interactions.py), and into one with a back turned to it within 2.2 m:
    a robot acting on "the robot joined" would interrupt. It stays in a group only within
    RING times the farthest member's distance of the others' o-space centre."""
    positions, headings = scene(*people, (0.0, 0.0, 0.0))
    unit = RoomScale(ScaleParams()).observe(positions[:-1], 0.0)
    labels = detect(positions, headings, P, unit)
    robot = len(people)
    ringed = on_the_ring(labels, positions, headings, P, unit, robot)
    grouped_with_robot = any(robot in g and len(g) > 1 for g in groups(ringed))
    assert grouped_with_robot is with_robot, (groups(labels), groups(ringed))
    people_groups = [sorted(set(g) - {robot}) for g in groups(labels)]
    assert [g for g in people_groups if len(g) > 1] == [
        g for g in ([sorted(set(g) - {robot}) for g in groups(ringed)]) if len(g) > 1
    ]  # people's groups are unchanged


def test_empty_and_one_person():
    assert detect(np.zeros((0, 2)), np.zeros(0), P).tolist() == []
    assert groups(detect(*scene((0, 0, 0)), P)) == []


@pytest.mark.parametrize("params", [P, gcff_params(0.5, 0.8)])
def test_people_in_one_spot_are_bounded_and_finite(params):
    positions = np.zeros((30, 2))
    headings = np.linspace(0, 2 * math.pi, 30, endpoint=False)
    labels = detect(positions, headings, params)
    assert len(labels) == 30 and labels.min() >= 0


def test_twenty_people_get_one_label_each_in_order_of_first_member():
    """The scene's crowd (what it costs is measured by benchmarks.perf.core, not asserted):
    labels 0..G-1, each person one, numbered in order of first member, the same each time."""
    rng = np.random.default_rng(0)
    positions, headings = rng.uniform(0, 6, (20, 2)), rng.uniform(0, 2 * math.pi, 20)
    labels = detect(positions, headings, P)
    assert labels.shape == (20,) and labels[0] == 0
    firsts = [int(np.flatnonzero(labels == g)[0]) for g in range(int(labels.max()) + 1)]
    assert firsts == sorted(firsts)
    assert (detect(positions, headings, P) == labels).all()


def test_group_ids_stay_while_most_members_stay_and_a_flicker_is_not_said():
    from facing_service.core.social.groups import GroupTracker

    tracker = GroupTracker(hold_s=0.3)
    abc = [(frozenset("abc"), (1.0, 0.0)), (frozenset("d"), (5.0, 5.0))]
    assert tracker.update(abc, 0.0) == ([], [])  # not held yet
    changed, gone = tracker.update(abc, 0.4)
    assert [(g.id, sorted(g.members)) for g in changed] == [(1, ["a", "b", "c"])] and gone == []
    # one frame of a different reading (a heading flickering): nothing said
    assert tracker.update([(frozenset("ab"), (1.0, 0.0))], 0.5) == ([], [])
    assert tracker.update(abc, 0.55) == ([], [])
    # d joins for good: the group keeps its id (it keeps most of its members)
    abcd = [(frozenset("abcd"), (1.5, 0.5))]
    tracker.update(abcd, 1.0)
    changed, gone = tracker.update(abcd, 1.4)
    assert [(g.id, sorted(g.members)) for g in changed] == [(1, ["a", "b", "c", "d"])]
    # it splits in two: the larger half keeps the id, the other is new
    split = [(frozenset("abc"), (1.0, 0.0)), (frozenset("d"), (5, 5)), (frozenset("ef"), (9, 9))]
    tracker.update(split, 2.0)
    changed, gone = tracker.update(split, 2.4)
    assert sorted((g.id, sorted(g.members)) for g in changed) == [
        (1, ["a", "b", "c"]),
        (2, ["e", "f"]),
    ]
    # everyone walks apart: both dissolve
    tracker.update([], 3.0)
    assert tracker.update([], 3.4) == ([], [1, 2])


def test_a_group_with_the_robot_says_so():
    from facing_service.core.social.groups import GroupTracker

    tracker = GroupTracker(hold_s=0.0)
    changed, _ = tracker.update([(frozenset({"", "alice"}), (0.5, 0.0))], 0.0)
    assert changed[0].robot and changed[0].members == {"", "alice"}


def test_one_parameter_set_groups_pairs_at_any_spacing_where_gcffs_stride_cannot():
    """Two people facing each other 0.8 m apart, and two 1.6 m apart: the stride from the
    nearest person ahead groups both; one fixed stride fits one spacing only."""
    close, far = scene((0, 0, 0), (0.8, 0, 180)), scene((0, 0, 0), (1.6, 0, 180))
    assert groups(detect(*close, P)) == [[0, 1]] and groups(detect(*far, P)) == [[0, 1]]
    fixed = gcff_params(0.3, 0.8)
    assert groups(detect(*close, fixed)) == [[0, 1]] and groups(detect(*far, fixed)) == []


def test_the_room_unit_makes_the_same_groups_wider_or_tighter_where_metres_do_not():
    """The learnt unit (measured by benchmarks.groups.held_out, not shipped):
    the same people standing wider or tighter make the same groups in the room's unit,
    the centres scaled. In metres (shipped), lengths are people's: a pair 3 m face to face
    (Hall's far social distance) still votes within a group's cost of one centre; 6 m
    apart, they fall apart."""
    room_params = ScaleParams(min_m=0.7, max_m=1.5)
    rng = np.random.default_rng(3)
    pairs = [((4.0 * k, 0.0, 0.0), (4.0 * k + 1.0, 0.0, 180.0)) for k in range(3)]
    positions, headings = scene(*[p for pair in pairs for p in pair], (2.0, 3.0, 90))
    headings = headings + rng.normal(0, 0.1, len(headings))
    labels, centres = detect_centres(positions, headings, P, 1.0)
    assert groups(labels) == [[0, 1], [2, 3], [4, 5]]
    for factor in (0.75, 1.4):  # within the unit's range (0.7 to 1.5 m)
        room = RoomScale(room_params)
        unit = room.observe(positions * factor, 0.0)
        assert unit == pytest.approx(factor * 1.0)  # everyone's nearest is 1 m (x factor)
        scaled, scaled_centres = detect_centres(positions * factor, headings, P, unit)
        assert scaled.tolist() == labels.tolist()
        assert np.allclose(scaled_centres, centres * factor)
    wide = positions * 3.0  # beyond the unit's range (1.5 m): still the same groups
    unit = RoomScale(room_params).observe(wide, 0.0)
    assert unit == 1.5 and groups(detect(wide, headings, P, unit)) == groups(labels)
    in_metres = RoomScale(ScaleParams()).observe(wide, 0.0)  # the shipped unit: metres
    assert in_metres == 1.0 and groups(detect(wide, headings, P, 1.0)) == groups(labels)
    assert groups(detect(positions * 6.0, headings, P, 1.0)) == []


def test_the_rooms_unit_is_learnt_over_its_window_kept_in_range_and_bounded():
    params = ScaleParams(window_s=10.0, min_m=0.5, max_m=1.5, default_m=1.0)
    room = RoomScale(params)
    alone = np.array([[1.0, 1.0]])
    assert room.observe(alone, 0.0) == 1.0  # one person says nothing: the default
    assert room.observe(np.array([[0.0, 0.0], [1.4, 0.0]]), 1.0) == 1.4
    assert room.observe(alone, 5.0) == 1.4  # still within the window
    assert room.observe(np.array([[0.0, 0.0], [0.7, 0.0]]), 6.0) == pytest.approx(1.05)
    assert room.observe(alone, 12.0) == pytest.approx(0.7)  # the 1.4 m frame left it
    assert room.observe(alone, 30.0) == 1.0  # nobody near anybody lately
    assert room.observe(np.array([[0.0, 0.0], [9.0, 0.0]]), 31.0) == 1.5  # loners: capped
    assert room.observe(np.array([[0.0, 0.0], [0.1, 0.0]]), 50.0) == 0.5
    fixed = RoomScale(ScaleParams(min_m=1.0, max_m=1.0))
    assert fixed.observe(np.array([[0.0, 0.0], [3.0, 0.0]]), 0.0) == 1.0  # metres
    for t in range(3 * RoomScale.MAX_KEPT):  # a fast caller: memory stays bounded
        room.observe(np.array([[0.0, 0.0], [1.0, 0.0]]), 60.0 + t * 1e-4)
    assert len(room._seen) == RoomScale.MAX_KEPT


def ring_of(count: int, spacing: float, centre=(3.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """``count`` people on a ring around ``centre``, ``spacing`` m between neighbours,
    each facing the centre."""
    radius = spacing / (2 * math.sin(math.pi / count))
    angles = np.arange(count) * 2 * math.pi / count
    positions = np.column_stack([centre[0] + radius * np.cos(angles), radius * np.sin(angles)])
    return positions, angles + math.pi


@pytest.mark.parametrize(("count", "spacing"), [(2, 1.2), (3, 0.9), (5, 0.8), (6, 0.8), (6, 0.6)])
def test_the_rings_stride_lands_every_vote_on_the_centre_whatever_its_size_and_count(
    count, spacing
):
    """The o-space's radius follows from the people's own spacing and count.
    A person votes for the point of their heading as far from the nearest person ahead
    as from themselves: on a ring facing its centre, that point is the centre (a pair
    face to face: the middle). The stride from the nearest person ahead alone (k * d)
    undershoots a circle of six by half."""
    from facing_service.core.social.groups import votes

    positions, headings = ring_of(count, spacing)
    ring = GroupParams(0.5, 0.25, 1.5, 70.0, 1.5, ring=True)
    assert np.allclose(votes(positions, headings, ring), [3.0, 0.0], atol=1e-9)
    assert groups(detect(positions, headings, ring)) == [list(range(count))]
    if count == 6:
        nearest = votes(positions, headings, replace(ring, ring=False))
        radius = spacing / (2 * math.sin(math.pi / count))
        assert np.allclose(np.hypot(*(nearest - [3.0, 0.0]).T), radius - spacing / 2)


rooms = st.lists(
    st.tuples(st.integers(-8, 8), st.integers(-8, 8), st.sampled_from([0, 90, 180, 270])),
    min_size=2,
    max_size=12,
    unique_by=lambda person: person[:2],
)  # GDet's kind: places on a grid, headings in 90-degree steps (exact ties everywhere)


@settings(max_examples=300, deadline=None)
@given(rooms, st.randoms(use_true_random=False))
def test_the_same_room_is_grouped_alike_whatever_order_its_people_come_in(room, rng):
    """A defect found: the greedy assignment broke ties in listing order, so the same room was
    grouped otherwise when its people were listed (or, through the service, named)
    otherwise."""
    positions, headings = scene(*((0.3 * x, 0.3 * y, h) for x, y, h in room))
    order = np.array(rng.sample(range(len(room)), len(room)))
    listed = {frozenset(g) for g in groups(detect(positions, headings, P))}
    reordered = groups(detect(positions[order], headings[order], P))
    assert {frozenset(order[g].tolist()) for g in reordered} == listed


def test_an_even_split_keeps_the_id_by_place_not_by_the_order_people_are_listed():
    """Before: which half of an evenly split group kept its id followed the order the
    halves were listed in (so, the people's names)."""
    from facing_service.core.social.groups import GroupTracker

    halves = [(frozenset("ab"), (1.0, 0.5)), (frozenset("cd"), (1.0, -0.2))]
    ids = []
    for listed in (halves, halves[::-1]):
        tracker = GroupTracker(hold_s=0.0)
        tracker.update([(frozenset("abcd"), (1.0, 0.0))], 0.0)
        tracker.update(listed, 1.0)
        ids.append({g.id: "".join(sorted(g.members)) for g in tracker.groups.values()})
    assert ids[0] == ids[1] == {1: "cd", 2: "ab"}  # cd stands nearer where the group was


def test_a_member_gone_is_said_at_once_while_a_regrouping_of_those_there_waits_its_hold():
    from facing_service.core.social.groups import GroupTracker

    tracker = GroupTracker(hold_s=0.3)
    abcd = [(frozenset("abcd"), (1.0, 0.0)), (frozenset({"", "e"}), (4.0, 0.0))]
    tracker.update(abcd, 0.0, set("abcde") | {""})
    (group, robots), _ = tracker.update(abcd, 0.4, set("abcde") | {""})
    # d is lost and, in the same reading, c looks away: d leaves at once, c waits
    reading = [(frozenset("ab"), (1.0, 0.0)), (frozenset("c"), (2.0, 0.0)),
               (frozenset({"", "e"}), (4.0, 0.0))]  # fmt: skip
    changed, gone = tracker.update(reading, 0.5, set("abce") | {""})
    assert [(g.id, g.members) for g in changed] == [(group.id, frozenset("abc"))] and gone == []
    changed, gone = tracker.update(reading, 0.9, set("abce") | {""})  # held: said
    assert [(g.id, g.members) for g in changed] == [(group.id, frozenset("ab"))]
    # e is lost: the robot alone is no group
    changed, gone = tracker.update(reading[:2], 1.0, set("abc") | {""})
    assert changed == [] and gone == [robots.id]
    # nobody said gone (present unknown): the hold as before
    assert tracker.update([], 1.1) == ([], [])
