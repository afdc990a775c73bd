"""The simulated crowd: deterministic, realistic enough, and a tracker's DELETEs."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from facing_service.client.sim import AREA_M, Crowd, simulate
from facing_service.contract.poses import Pose, decode_pose
from facing_service.core.detector import classify


def run(crowd: Crowd, steps: int, dt: float = 0.1):
    return [crowd.step(dt) for _ in range(steps)]


def test_the_same_seed_gives_the_same_crowd_and_another_seed_another():
    assert run(Crowd(people=5, seed=3), 300) == run(Crowd(people=5, seed=3), 300)
    assert run(Crowd(people=5, seed=3), 50) != run(Crowd(people=5, seed=4), 50)


def test_people_leave_with_a_delete_and_others_arrive():
    crowd = Crowd(people=5, seed=1)
    ticks = run(crowd, 3000)  # five minutes at 10 Hz
    lost = [body for f in ticks for body in f.lost]
    assert lost, "nobody ever left"
    assert len(set(lost)) == len(lost)  # each person leaves once
    for i, tick in enumerate(ticks):
        ids = {p.body_id for p in tick.poses}
        assert len(ids) == 5  # the crowd is topped up
        assert not ids & set(tick.lost)
        assert not ids & {b for f in ticks[:i] for b in f.lost}  # lost ids never return


def test_stamps_strictly_increase_and_poses_stay_near_the_robot():
    ticks = run(Crowd(people=5, seed=2), 600)
    stamps = [(f.poses[0].sec, f.poses[0].nanosec) for f in ticks]
    assert all(a < b for a, b in itertools.pairwise(stamps))
    assert all(math.hypot(p.x, p.y) < 2.5 * AREA_M for f in ticks for p in f.poses)


def test_people_turn_toward_and_away_from_the_robot():
    ticks = run(Crowd(people=5, seed=0), 600)
    facing_share = []
    for f in ticks:
        half = np.radians([p.yaw_deg for p in f.poses]) / 2
        t = np.array([[p.x, p.y, 0.0] for p in f.poses])
        q = np.stack([np.zeros_like(half), np.zeros_like(half), np.sin(half), np.cos(half)], 1)
        facing_share.append(classify(t, q, 20.0).facing.mean())
    assert 0.05 < np.mean(facing_share) < 0.8  # some facing, not everybody all the time
    assert min(facing_share) < max(facing_share)


def test_jitter_like_a_tracker():
    """Someone standing still, facing the robot, is not published at a constant pose."""
    crowd = Crowd(people=1, seed=5)
    yaws = [f.poses[0].yaw_deg for f in run(crowd, 200)]
    steps = np.abs(np.diff(yaws))
    assert np.median(steps) > 0.5  # degrees of noise from one frame to the next


class FakeTime:
    """The simulator's clock, advanced by its own sleeps: a 20 s crowd takes no 20 s."""

    def __init__(self) -> None:
        self.now = 0.0
        self.slept = 0.0

    def clock(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.now += seconds
        self.slept += seconds


def test_simulate_publishes_valid_poses_and_deletes():
    published: list[tuple[str, bytes | None]] = []
    time = FakeTime()
    ticks = simulate(
        lambda key, payload: published.append((key, payload)),
        Crowd(people=3, seed=1),
        "base_link",
        rate_hz=1000.0,
        duration_s=20.0,
        clock=time.clock,
        sleep=time.sleep,
    )
    assert ticks == 20_000
    assert time.slept == pytest.approx(20.0)  # paced in real time, on the clock it is given
    puts = [(k, p) for k, p in published if p is not None]
    deletes = [k for k, p in published if p is None]
    assert deletes and all(k.endswith("/pose/base_link") for k in deletes)
    key, payload = puts[0]
    body_id = key.split("/")[2]
    assert isinstance(decode_pose(payload, body_id, "base_link"), Pose)


def test_simulate_says_everyone_still_there_is_gone_when_it_stops():
    """Before, a run ended with its people's poses just stopping: a service read that as a
    stalled link, held them for --hold-silent-s and said the input was gone."""
    published: list[tuple[str, bytes | None]] = []
    time = FakeTime()
    crowd = Crowd(people=3, seed=1)
    simulate(
        lambda key, payload: published.append((key, payload)), crowd, "base_link",
        rate_hz=30.0, duration_s=1.0, clock=time.clock, sleep=time.sleep,
    )  # fmt: skip
    tail = published[-3:]
    assert all(payload is None for _, payload in tail)
    assert sorted(k.split("/")[2] for k, _ in tail) == sorted(crowd.present()) != []
