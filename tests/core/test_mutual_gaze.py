"""Visual social engagement (core.mutual_gaze) as hri_engagement 2.0.1 computes it, from
a face's pose: hand-worked values of its formula, and the gaze frame's optical convention
(what hri_engagement reads) giving the same score as the face's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from facing_service.core import detector
from facing_service.core.mutual_gaze import GazeParams, from_gaze_pose, score, votes_engaged

P = GazeParams()
LOG5 = math.log(5.0)


def test_squarely_facing_at_one_and_two_metres():
    # the robot 1 m ahead of the face, the face 1 m ahead of the robot: both gazes 1
    assert score((1.0, 0.0, 0.0), (1.0, 0.0, 0.0), P) == pytest.approx(math.log(4) / LOG5)
    assert score((2.0, 0.0, 0.0), (2.0, 0.0, 0.0), P) == pytest.approx(math.log(3) / LOG5)


def test_the_robot_off_the_persons_axis_falls_with_the_tangent_over_tan_60():
    off = math.radians(30)
    robot = (math.cos(off), math.sin(off), 0.0)  # 1 m away, 30 deg off the face's axis
    expected = (1 - math.tan(off) / math.tan(math.radians(60))) * math.log(4) / LOG5
    assert score(robot, (1.0, 0.0, 0.0), P) == pytest.approx(expected)
    assert score((-1.0, 0.0, 0.0), (1.0, 0.0, 0.0), P) == 0.0  # the robot behind the face


def test_beyond_the_distance_there_is_no_score_and_no_engaged_vote():
    assert score((4.1, 0.0, 0.0), (4.1, 0.0, 0.0), P) is None
    assert not votes_engaged((4.1, 0.0, 0.0), (4.1, 0.0, 0.0), P)
    assert votes_engaged((1.0, 0.0, 0.0), (1.0, 0.0, 0.0), P)  # 0.86 > 0.5
    assert not votes_engaged((1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), P)  # behind the robot


#: REP 155: a face's gaze frame has the face's origin, z along the face's x, x to its
#: right (-y), y down (-z): the gaze's axes (columns) in the face's.
FACE_TO_GAZE = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])


def quaternion(m: np.ndarray) -> tuple[float, float, float, float]:
    w = math.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + m[0, 0] - m[1, 1] - m[2, 2])) / 2, m[2, 1] - m[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - m[0, 0] + m[1, 1] - m[2, 2])) / 2, m[0, 2] - m[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - m[0, 0] - m[1, 1] + m[2, 2])) / 2, m[1, 0] - m[0, 1])
    return (x, y, z, w)


def rotation(yaw: float, pitch: float) -> np.ndarray:
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    return np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]]) @ np.array(
        [[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]]
    )


@given(
    st.floats(0.3, 3.5), st.floats(-0.6, 0.6), st.floats(-0.5, 0.5),
    st.floats(-math.pi, math.pi), st.floats(-0.8, 0.8),
)  # fmt: skip
def test_the_gaze_frame_and_the_face_frame_give_one_score(x, y, z, yaw, pitch):
    """hri_engagement reads the gaze frame (the robot's offset from its optical z axis);
    the service reads the face frame (from its x axis): one score."""
    face = rotation(yaw, pitch)
    t = (x, y, z)
    robot = tuple(detector.robot_in_body(np.array([t]), np.array([quaternion(face)]))[0])
    from_gaze, person = from_gaze_pose(t, quaternion(face @ FACE_TO_GAZE))
    assert from_gaze == pytest.approx(robot, abs=1e-7)
    assert score(from_gaze, person, P) == pytest.approx(score(robot, t, P), abs=1e-7)
