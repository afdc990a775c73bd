"""The core's records: a batch decided at once is decided as one by one, a frame's lists
are shared by a journal copy until the first change, the aggregate is sorted."""

from __future__ import annotations

import copy
import math

from facing_service.config.profiles import engagement_params
from facing_service.config.settings import Settings
from facing_service.contract.keys import BodyRef
from facing_service.contract.poses import Pose
from facing_service.contract.stamps import Time
from facing_service.core import detector
from facing_service.core.records import Frame, PoseSample, Profile, decide, frame_facing

BODY = Profile(20.0, 5.0, False, engagement_params(Settings()))


def sample(i: int) -> PoseSample:
    """Body i at 2 m, turned i degrees from facing the robot."""
    yaw = math.radians(180.0 + i)
    pose = Pose(Time.of(1), (2.0, 0.0, 0.0), (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)))
    return PoseSample(BodyRef(frame_id="cam", body_id=f"b{i}"), pose)


def test_a_batch_is_decided_as_each_sample_alone():
    many = [sample(i) for i in range(detector.SMALL_BATCH + 5)]
    n = len(many)
    batch = decide(many, [20.0] * n, [BODY] * n, [20.0] * n)
    alone = [decide([s], [20.0], [BODY], [20.0])[0] for s in many]
    assert [(b.facing, b.body_id) for b in batch] == [(a.facing, a.body_id) for a in alone]
    assert all(math.isclose(b.angle_deg, a.angle_deg, abs_tol=1e-9)
               for b, a in zip(batch, alone, strict=True))  # fmt: skip
    assert [b.facing for b in batch[:25]] == [True] * 20 + [False] * 5


def test_a_frame_copy_shares_its_lists_until_either_changes():
    frame = Frame()
    frame.update("a", True)
    kept = copy.copy(frame)  # what the journal keeps for a rollback
    frame.update("b", False)
    assert kept.tracked == {"a"} and frame.tracked == {"a", "b"} and frame.dirty
    frame.dirty = False
    frame.update("a", True)  # nothing changed: not dirty
    assert not frame.dirty


def test_the_aggregate_lists_are_sorted():
    said = frame_facing("cam", Time.of(2), ["c", "a"], ["c", "b", "a"])
    assert said.bodies_facing == ["a", "c"] and said.bodies_tracked == ["a", "b", "c"]
    assert frame_facing("cam", None, [], []).stamp is None
