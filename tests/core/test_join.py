"""Where the robot should stand to join a group, or to greet a person: pure."""

from __future__ import annotations

import math

import numpy as np
import pytest

from facing_service.core.social.join import JoinParams, join_pose, o_space

P = JoinParams()


def ring(n: int, radius: float, skip: set[int] = frozenset(), centre=(3.0, 0.0)):
    """``n`` places around a circle (those in ``skip`` left empty), each facing its centre."""
    angles = [2 * math.pi * k / n for k in range(n) if k not in skip]
    xy = np.array(
        [(centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a)) for a in angles]
    )
    headings = np.array([a + math.pi for a in angles])
    return xy, headings


def test_a_group_with_a_gap_is_joined_in_the_gap_on_its_ring_facing_in():
    members, headings = ring(4, 0.8, skip={2})  # the place at 180° (x = 2.2) is empty
    pose = join_pose(members, headings, np.zeros((0, 2)), (0.0, 0.0), P)
    assert pose is not None
    # in the gap, near where the fourth would stand (the centre the three remaining give
    # is pulled toward them: 0.2 m inside the true ring)
    assert (pose.x, pose.y) == pytest.approx((2.2, 0.0), abs=0.25)
    assert math.hypot(pose.x - 3.0, pose.y) == pytest.approx(0.8, abs=0.25)
    assert math.degrees(pose.yaw) == pytest.approx(0.0, abs=6)  # facing into the group
    gap = np.hypot(*(members - [pose.x, pose.y]).T).min()
    spacing = math.hypot(*(members[0] - members[1]))
    assert gap >= P.clearance_k * spacing  # no closer than they stand to each other


def test_of_several_free_places_the_one_nearest_the_robot():
    """A pair facing each other leaves room on both sides: the robot takes its own side."""
    members = np.array([[3.0, 0.6], [3.0, -0.6]])
    headings = np.array([-math.pi / 2, math.pi / 2])
    near = join_pose(members, headings, np.zeros((0, 2)), (0.0, 0.0), P)
    far = join_pose(members, headings, np.zeros((0, 2)), (6.0, 0.0), P)
    assert near is not None and far is not None
    assert near.x < 3.0 < far.x


def test_someone_standing_in_the_gap_takes_the_room():
    """The gap was the only room: with someone in it there is none. (a defect found:
    this test passed whenever join_pose returned None, and so could not fail on it; a
    join_pose blind to outsiders now fails it, and the place beside one is checked.)"""
    members, headings = ring(4, 0.8, skip={2})
    outsider = np.array([[2.2, 0.0]])  # not a member, but there
    assert join_pose(members, headings, outsider, (0.0, 0.0), P) is None
    assert join_pose(members, headings, np.zeros((0, 2)), (0.0, 0.0), P) is not None


def test_a_place_beside_someone_keeps_its_distance():
    members, headings = ring(4, 0.8, skip={2})
    beside = np.array([[2.2, 0.3]])  # in the gap's edge: the rest of the gap is still free
    pose = join_pose(members, headings, beside, (0.0, 0.0), P)
    assert pose is not None
    assert math.hypot(pose.x - 2.2, pose.y - 0.3) >= P.min_clearance_m


def test_a_closed_ring_has_no_room():
    members, headings = ring(8, 0.8)  # eight people 0.61 m apart around 0.8 m
    assert join_pose(members, headings, np.zeros((0, 2)), (0.0, 0.0), P) is None


def test_the_o_space_centre_is_in_front_of_an_open_arc():
    """Two people side by side facing the same place: their centroid is between them, the
    place they share is in front."""
    members = np.array([[2.0, 0.4], [2.0, -0.4]])
    headings = np.array([0.0, 0.0])
    centre, _ = o_space(members, headings, P)
    assert centre[0] > 2.0


def _around(centre, radius, degrees):
    xy = np.array([(centre[0] + radius * math.cos(math.radians(a)),
                    centre[1] + radius * math.sin(math.radians(a))) for a in degrees])  # fmt: skip
    return xy, np.array([math.radians(a) + math.pi for a in degrees])


#: Three members at 0°, 80° and 180° of a ring of 1 m around (3, 0): the room the group
#: leaves is the half ring from 180° to 360° (a fourth stood at 270°); between the two
#: members at 80° and 180° a narrow sliver is clear too.
GAP_AND_SLIVER = _around((3.0, 0.0), 1.0, (0, 80, 180))


def test_the_group_says_where_to_stand_not_where_the_robot_is():
    """A defect found: the free arc nearest the robot won, so a robot behind the group, by the
    sliver, was sent to the sliver; a person joining takes the room the group leaves."""
    members, headings = GAP_AND_SLIVER
    behind = (3.0 + 4 * math.cos(math.radians(130)), 4 * math.sin(math.radians(130)))
    pose = join_pose(members, headings, np.zeros((0, 2)), behind, P)
    assert pose is not None
    where = math.degrees(math.atan2(pose.y, pose.x - 3.0)) % 360
    assert 230 <= where <= 310, where  # in the room left, where the fourth stood (270°)
    assert abs(math.degrees(math.remainder(pose.yaw - math.radians(where + 180), math.tau))) < 25


def test_a_group_with_one_clear_gap_is_joined_there_from_anywhere():
    """The target: the place moves no more than 0.1 m with where the robot stands
    (four directions at 2 and 4 m, and far away); it does not move at all."""
    members, headings = GAP_AND_SLIVER
    robots = [
        (3.0 + r * math.cos(a), r * math.sin(a))
        for r in (2.0, 4.0, 40.0)
        for a in np.linspace(0, 2 * math.pi, 8, endpoint=False)
    ]
    places = {(p.x, p.y) for p in (join_pose(members, headings, np.zeros((0, 2)), robot, P)
                                   for robot in robots) if p is not None}  # fmt: skip
    assert len(places) == 1


def test_a_group_beside_another_is_joined_on_its_own_free_side():
    """A pair facing each other, another pair standing close on one side: the room is the
    other side, wherever the robot is."""
    members = np.array([[3.0, 0.6], [3.0, -0.6]])
    headings = np.array([-math.pi / 2, math.pi / 2])
    neighbours = np.array([[4.1, 0.35], [4.1, -0.35]])  # at x > 3: that side is narrowed
    for robot in ((6.0, 0.0), (0.0, 0.0), (3.0, 5.0)):
        pose = join_pose(members, headings, neighbours, robot, P)
        assert pose is not None and pose.x < 3.0, robot


def test_two_people_a_hand_apart_leave_a_place_at_a_conversations_distance():
    """Synth's pairs 0.2 m apart, turned 120° to each other: their ring is 0.1 m across
    the centre, too small for anyone (no place was given); the ring is at least
    ``min_radius_m``, so a place is, that far from the centre and clear of both."""
    members = np.array([[-3.0, 0.1], [-3.0, -0.1]])
    headings = np.radians([240.0, 120.0])
    assert join_pose(members, headings, np.zeros((0, 2)), (0.0, 0.0),
                     JoinParams(min_radius_m=0.0)) is None  # fmt: skip
    pose = join_pose(members, headings, np.zeros((0, 2)), (0.0, 0.0), P)
    assert pose is not None
    centre, radius = o_space(members, headings, P)
    assert radius == P.min_radius_m == 0.4
    assert math.hypot(pose.x - centre[0], pose.y - centre[1]) == pytest.approx(0.4)
    assert np.hypot(*(members - [pose.x, pose.y]).T).min() >= P.min_clearance_m
