"""Where the robot should stand to join a group, or to greet a person (issue 53): pure."""

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
    """The gap was the only room: with someone in it there is none. (Issue 63, defect 7:
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
