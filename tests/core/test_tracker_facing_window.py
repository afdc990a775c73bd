"""A face's facing decision over a window of its poses (``--head-facing-window-s``): the
median angle follows what most poses say, so a face tracker's frame-to-frame swings no
longer flip it, a real turn is said about half the window later, and with no window (and
no hysteresis) the rule is exact pose by pose."""

from __future__ import annotations

import itertools
import math

from hypothesis import given, settings
from hypothesis import strategies as st

from facing_service.config.profiles import head_profile, tracker_for
from facing_service.config.settings import Settings
from facing_service.contract.keys import BodyRef
from facing_service.contract.poses import Pose, yaw_rotation
from facing_service.contract.stamps import NS_PER_S, Time
from facing_service.core import detector
from facing_service.core.records import MAX_WINDOW, PoseSample, windowed

RATE_HZ = 30.0


def face(i: int, away_deg: float, name: str = "f1") -> PoseSample:
    """Face ``name`` 2 m ahead, turned ``away_deg`` from the robot, at frame ``i``."""
    stamp = Time(round((1.0 + i / RATE_HZ) * NS_PER_S))
    pose = Pose(stamp, (2.0, 0.0, 0.0), yaw_rotation(180.0 + away_deg))
    return PoseSample(BodyRef(frame_id="base_link", body_id=name), pose, "head")


def said(angles: list[float], **settings_given: float) -> list[bool]:
    """The facing decisions published for a face turned by ``angles``, one pose a frame."""
    tracker = tracker_for(Settings(**settings_given))
    out = []
    for i, angle in enumerate(angles):
        (state,) = tracker.ingest([face(i, angle)], 1.0 + i / RATE_HZ).results
        out.append(state.facing)
    return out


def test_a_face_alternating_between_two_estimates_no_longer_flickers():
    """ghfbv's tracker gave about 15° and 55° in turn: 71 flips in 10 s, pose by pose."""
    swinging = [15.0, 55.0] * 60
    pose_by_pose = said(swinging, head_facing_window_s=0.0)
    assert sum(a != b for a, b in itertools.pairwise(pose_by_pose)) > 100
    held = said(swinging, head_facing_window_s=0.4)
    assert sum(a != b for a, b in itertools.pairwise(held[1:])) == 0


def test_a_frame_or_two_astray_changes_nothing():
    looking = [10.0] * 30
    for i in (5, 12, 13, 20):
        looking[i] = 60.0
    assert all(said(looking, head_facing_window_s=0.4))
    away = [60.0] * 30
    for i in (5, 12, 13, 20):
        away[i] = 5.0
    assert not any(said(away, head_facing_window_s=0.4)[1:])


def test_a_turn_toward_the_robot_is_said_about_half_the_window_later():
    for window in (0.2, 0.4, 1.0):
        decided = said([60.0] * 30 + [0.0] * 60, head_facing_window_s=window)
        first = decided.index(True)
        late_s = (first - 30) / RATE_HZ
        assert window / 2 - 1 / RATE_HZ <= late_s <= window / 2 + 1 / RATE_HZ, (window, late_s)
        assert all(decided[first:])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.0, 179.0), min_size=1, max_size=60))
def test_no_window_and_no_hysteresis_is_the_tutorials_rule_pose_by_pose(angles):
    threshold = head_profile(Settings()).threshold_deg
    decided = said(angles, head_facing_window_s=0.0, hysteresis_deg=0.0, head_cone="planar")
    expected = []
    for i, angle in enumerate(angles):
        pose = face(i, angle).pose
        expected.append(detector.classify_one(pose.translation, pose.rotation, threshold)[3])
    assert decided == expected


def test_many_faces_at_once_are_decided_as_one_at_a_time():
    """Past ``SMALL_BATCH`` faces a batch takes the vectorized path: the same window."""
    n = detector.SMALL_BATCH + 3
    many, alone = tracker_for(Settings()), tracker_for(Settings())
    together, each = [], []
    for i in range(24):
        batch = [face(i, (37.0 * (i + k)) % 60.0, f"f{k}") for k in range(n)]
        together += [s.facing for s in many.ingest(batch, 1.0 + i / RATE_HZ).results]
        for sample in batch:
            each += [s.facing for s in alone.ingest([sample], 1.0 + i / RATE_HZ).results]
    assert together == each and any(together) and not all(together)


def test_a_window_holds_at_most_its_bound_whatever_the_rate():
    recent: tuple[tuple[int, float], ...] = ()
    for i in range(1000):  # 1 kHz for a second, in a 2 s window
        _, recent = windowed(recent, i * NS_PER_S // 1000, 10.0, 2.0, 20.0, False)
    assert len(recent) == MAX_WINDOW
    assert math.isclose(recent[-1][0], 999 * NS_PER_S // 1000)
