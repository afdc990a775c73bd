"""Decisions over time, with an injected clock and no network."""

from __future__ import annotations

import copy
import math

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from facing_service.contract.keys import BodyRef
from facing_service.contract.levels import Level
from facing_service.contract.poses import Pose
from facing_service.contract.stamps import Time
from facing_service.core.records import Frame, PoseSample
from facing_service.core.tracker import Tracker

from trackers import sample, tracker

A = BodyRef(frame_id="cam", body_id="a")


def test_first_pose_yields_a_result_and_a_frame_change():
    t = tracker()
    changes = t.ingest([sample(off_deg=10.0)], now=0.0)
    (state,) = changes.results
    assert state.facing and state.angle_deg == pytest.approx(10.0)
    assert state.distance_m == pytest.approx(2.0) and state.threshold_deg == 20.0
    (frame,) = changes.frames
    assert frame.bodies_facing == ["a"] and frame.bodies_tracked == ["a"]
    assert frame.stamp is not None and frame.stamp.sec == 1
    assert state.stamp == Time.of(1)


def test_frame_aggregate_only_when_a_list_changes():
    t = tracker()
    t.ingest([sample(off_deg=10.0, sec=1)], now=0.0)
    assert t.ingest([sample(off_deg=12.0, sec=2)], now=0.1).frames == []
    changes = t.ingest([sample(off_deg=40.0, sec=3)], now=0.2)
    assert [f.bodies_facing for f in changes.frames] == [[]]
    assert changes.frames[0].bodies_tracked == ["a"]


def test_older_stamp_is_refused_and_equal_stamp_accepted():
    t = tracker()
    t.ingest([sample(sec=5, off_deg=10.0)], now=0.0)
    changes = t.ingest([sample(sec=4, nanosec=999_999_999, off_deg=50.0)], now=0.1)
    assert changes.results == [] and len(changes.out_of_order) == 1
    assert t.states()[0].facing  # the refused pose changed nothing
    assert len(t.ingest([sample(sec=5, off_deg=11.0)], now=0.2).results) == 1


def test_out_of_order_inside_one_batch():
    t = tracker()
    changes = t.ingest([sample(sec=3), sample(sec=2), sample(sec=4)], now=0.0)
    assert [s.stamp.sec for s in changes.results] == [3, 4]
    assert [s.pose.stamp for s in changes.out_of_order] == [Time.of(2)]


@pytest.mark.parametrize(
    ("hysteresis", "angles", "expected"),
    [
        (5.0, [18, 23, 24.9, 26, 23, 19.9], [True, True, True, False, False, True]),
        (0.0, [18, 23, 19, 20, 19.99], [True, False, True, False, True]),
    ],
)
def test_hysteresis(hysteresis, angles, expected):
    t = tracker(hysteresis_deg=hysteresis)
    decided = [
        t.ingest([sample(off_deg=a, sec=i + 1)], now=i * 0.1).results[0].facing
        for i, a in enumerate(angles)
    ]
    assert decided == expected


def test_one_body_twice_in_a_batch_is_decided_in_order_with_hysteresis():
    t = tracker()
    changes = t.ingest([sample(off_deg=18, sec=1), sample(off_deg=23, sec=2)], now=0.0)
    assert [(s.stamp.sec, s.facing) for s in changes.results] == [(1, True), (2, True)]
    t2 = tracker()
    changes = t2.ingest([sample(off_deg=23, sec=1), sample(off_deg=18, sec=2)], now=0.0)
    assert [s.facing for s in changes.results] == [False, True]


def test_bodies_are_independent_per_frame():
    t = tracker()
    changes = t.ingest(
        [sample("a", "cam", off_deg=5), sample("a", "map", off_deg=60), sample("b", "cam")],
        now=0.0,
    )
    assert len(changes.results) == 3
    frames = {f.frame_id: f for f in changes.frames}
    assert frames["cam"].bodies_facing == ["a", "b"]
    assert frames["map"].bodies_facing == [] and frames["map"].bodies_tracked == ["a"]
    assert len(t) == 3


def test_lose_removes_the_body_and_updates_the_frame():
    t = tracker()
    t.ingest([sample("a"), sample("b", off_deg=90)], now=0.0)
    changes = t.lose(A, 0.0)
    assert changes.lost == [("cam", "a")]
    assert changes.frames[0].bodies_facing == [] and changes.frames[0].bodies_tracked == ["b"]
    assert t.lose(A, 0.0).lost == []  # already gone: nothing to publish
    assert t.lose(BodyRef(frame_id="nowhere", body_id="zzz"), 0.0).lost == []


def test_a_loss_says_when_it_happened():
    """A defect found: ``lose`` defaulted ``now`` to 0.0; on a monotonic clock (hours
    since boot) a tombstone stamped at 0 had expired before it was made, and a late pose
    brought back the body its tracker had just deleted. The time is the caller's to say."""
    t = tracker()
    t.ingest([sample("a", sec=5)], now=3600.0)
    with pytest.raises(TypeError):
        t.lose(A)  # type: ignore[call-arg]
    t.lose(A, 3600.5)
    late = t.ingest([sample("a", sec=4)], now=3600.6)  # stamped before the loss
    assert late.results == [] and len(t) == 0


def test_losing_many_bodies_at_once_says_one_aggregate():
    """A tracked list replacing N ids used to publish N aggregates, each listing everyone
    left (1 000 ids: 42 MB out): now N DELETEs and one aggregate per frame."""
    t = tracker()
    t.ingest([sample(f"b{i}", sec=1) for i in range(1000)], now=0.0)
    gone = [BodyRef(frame_id="cam", body_id=f"b{i}") for i in range(1000)]
    changes = t.lose(gone, now=0.0)
    assert len(changes.lost) == 1000
    (frame,) = changes.frames
    assert frame.bodies_tracked == []


def test_staleness_on_the_injected_clock():
    t = tracker(stale_after_s=2.0)
    t.ingest([sample("a", sec=1)], now=10.0)
    t.ingest([sample("b", sec=1)], now=11.0)
    assert t.next_expiry() == 12.0
    assert t.expire(11.99).lost == []
    t.ingest([sample("a", sec=2)], now=11.5)  # a refreshed: b is now the oldest
    assert t.next_expiry() == 13.0
    changes = t.expire(13.0)
    assert changes.lost == [("cam", "b")]
    assert changes.frames[0].bodies_tracked == ["a"]
    assert t.expire(13.5).lost == [("cam", "a")]
    assert t.next_expiry() is None


def test_evaluate_is_a_what_if_without_hysteresis():
    t = tracker()
    t.ingest([sample("a", off_deg=18, sec=1)], now=0.0)
    t.ingest([sample("a", off_deg=23, sec=2)], now=0.1)  # facing by hysteresis
    t.ingest([sample("b", off_deg=30, sec=1)], now=0.1)
    states, frames = t.evaluate(35.0)
    assert {s.body_id: s.facing for s in states} == {"a": True, "b": True}
    assert all(s.threshold_deg == 35.0 for s in states)
    assert frames[0].bodies_facing == ["a", "b"]
    states, frames = t.evaluate(20.0)
    assert {s.body_id: s.facing for s in states} == {"a": False, "b": False}
    # the service's own state is untouched
    assert {s.body_id: s.facing for s in t.states()} == {"a": True, "b": False}
    assert t.frames()[0].bodies_facing == ["a"]


def test_declared_frame_is_known_before_any_pose():
    t = tracker(frames=["cam"])
    (frame,) = t.frames()
    assert frame.stamp is None and frame.bodies_tracked == []
    assert t.evaluate(30.0) == ([], t.frames())


def test_degenerate_pose_is_tracked_not_facing():
    t = tracker()
    pose = Pose(Time.of(1), (0.0, 0.0, -1.0), (0.0, 0.0, 0.0, 1.0))
    (state,) = t.ingest([PoseSample(A, pose)], now=0.0).results
    assert not state.facing and state.angle_deg is None and state.distance_m is None
    assert math.isfinite(state.robot_in_body[2])


def test_capacity_refuses_new_bodies_but_keeps_updating_known_ones():
    t = tracker(max_bodies=2)
    changes = t.ingest([sample("a"), sample("b"), sample("c"), sample("a", "map")], now=0.0)
    assert [(s.frame_id, s.body_id) for s in changes.results] == [("cam", "a"), ("cam", "b")]
    assert [(s.frame_id, s.body_id) for s in changes.over_capacity] == [
        ("cam", "c"),
        ("map", "a"),
    ]
    assert len(t.ingest([sample("a", sec=2), sample("b", sec=2)], now=0.1).results) == 2
    t.lose(A, 0.15)
    changes = t.ingest([sample("c"), sample("d")], now=0.2)
    assert [s.body_id for s in changes.results] == ["c"]
    assert [s.body_id for s in changes.over_capacity] == ["d"]
    assert len(t) == 2


def test_a_flood_of_unique_ids_stays_at_the_bound():
    t = tracker(max_bodies=1000)
    refused = 0
    for start in range(0, 20_000, 500):
        batch = [sample(f"id{i}", f"frame{i % 7}") for i in range(start, start + 500)]
        refused += len(t.ingest(batch, now=start / 1e4).over_capacity)
    assert len(t) == 1000 and refused == 19_000
    assert sum(t.tracked_per_frame().values()) == 1000


def test_undeclared_frames_are_forgotten_when_empty_declared_ones_are_kept():
    t = tracker(frames=["cam"])
    t.ingest([sample("a", "cam"), sample("a", "tmp")], now=0.0)
    assert t.tracked_per_frame() == {"cam": 1, "tmp": 1}
    changes = t.expire(10.0)
    assert {f.frame_id: f.bodies_tracked for f in changes.frames} == {"cam": [], "tmp": []}
    assert t.tracked_per_frame() == {"cam": 0}
    assert [f.frame_id for f in t.frames()] == ["cam"]


# -- no ghosts: tombstones, and time that moves without samples --------------------------


def test_a_late_pose_never_brings_back_a_deleted_body():
    t = tracker()
    t.ingest([sample(sec=5)], now=0.0)
    t.lose(A, now=1.0)
    late = t.ingest([sample(sec=4), sample(sec=5)], now=2.0)
    assert late.results == [] and len(late.out_of_order) == 2
    back = t.ingest([sample(sec=6)], now=3.0)  # newer than the DELETE: really back
    assert [s.body_id for s in back.results] == ["a"]


def test_tombstones_are_bounded_in_number_and_time():
    t = tracker(max_bodies=3)
    for i in range(10):
        t.ingest([sample(body=f"b{i}", sec=5)], now=0.0)
        t.lose(BodyRef(frame_id="cam", body_id=f"b{i}"), now=0.0)
    assert len(t._tombstones) == 3  # the oldest ones went first
    assert t.ingest([sample(body="b0", sec=5)], now=1.0).results  # b0's tombstone is gone
    t.expire(now=10_000.0)
    assert len(t._tombstones) == 0


def test_a_silent_body_disengages_on_time():
    """ENGAGED, then looking away (DISENGAGING), then the tracker stops publishing: the
    level still reaches DISENGAGED after its dwell, on the caller's clock."""
    t = tracker(stale_after_s=60.0)
    now = 0.0
    levels = []
    for i in range(60):  # 2 s facing at 30 Hz
        now = i / 30
        changes = t.ingest([sample(sec=0, nanosec=int(now * 1e9))], now=now)
        levels += [u.level for u in changes.engagement if u.previous is not None]
    for i in range(60, 75):  # turns away for 0.5 s
        now = i / 30
        changes = t.ingest([sample(off_deg=90.0, sec=int(now), nanosec=int(now % 1 * 1e9))], now)
        levels += [u.level for u in changes.engagement if u.previous is not None]
    assert levels[-1] is Level.DISENGAGING
    due = t.next_due()
    assert due is not None and due > now  # the dwell, from the last sample
    assert t.advance(now=due - 0.01).engagement == []
    (update,) = t.advance(now=due + 0.01).engagement
    assert update.level is Level.DISENGAGED and update.previous is Level.DISENGAGING
    assert t.next_due() is None


def _everything(t: Tracker) -> tuple:
    """All a tracker would ever say or decide from, in the order it would (frames in any
    order: a rolled-back frame may come back last among them, which nothing reads)."""
    return (
        t.states(),
        sorted(t.frames(), key=lambda f: f.frame_id),
        t.engagements(),
        t.next_expiry(),
        t.next_due(),
        list(t._tombstones.items()),
        [(k, tr.last_seen) for k, tr in t._tracks.items()],
        {f: (fr.dirty, fr.stamp, fr.tracked, fr.facing) for f, fr in t._frames.items()},
    )


_OPS = st.lists(
    st.tuples(
        st.sampled_from(["ingest", "lose", "expire", "advance"]),
        st.sampled_from(["a", "b", "c"]),
        st.sampled_from(["cam", "map"]),
        st.sampled_from([0, 60]),  # off-axis degrees: facing or not
        st.integers(1, 30),  # stamp, seconds
    ),
    max_size=16,
)


def _do(t: Tracker, op: tuple, now: float) -> None:
    what, body, frame, off, sec = op
    if what == "ingest":
        t.ingest([sample(body, frame, off_deg=off, sec=sec)], now)
    elif what == "lose":
        t.lose(BodyRef(frame_id=frame, body_id=body), now)
    elif what == "expire":
        t.expire(now)
    else:
        t.advance(now)


_ENGAGED_THEN_AWAY = [("ingest", "a", "cam", 0, sec) for sec in range(1, 9)] + [
    ("ingest", "a", "cam", 60, 9)
]


@given(before=_OPS, inside=_OPS)
@example(before=_ENGAGED_THEN_AWAY, inside=[("advance", "a", "cam", 0, 1)] * 6)  # the dwell
@settings(max_examples=300, deadline=None)
def test_a_transaction_that_raises_leaves_the_tracker_as_it_was(before, inside):
    """The service wraps each tracker call and the building of its publications in a
    transaction: whatever the calls inside changed, an exception puts everything back,
    orders included (expiry pops the oldest first)."""
    t, t2 = tracker(max_bodies=2), tracker(max_bodies=2)
    for i, op in enumerate(before):
        _do(t, op, now=i * 0.7)
        _do(t2, op, now=i * 0.7)
    now = len(before) * 0.7
    with pytest.raises(RuntimeError), t.transaction():
        for i, op in enumerate(inside):
            _do(t, op, now + i * 0.7)
        raise RuntimeError("building the publications failed")
    assert _everything(t) == _everything(t2)
    for i, op in enumerate(inside):  # and it goes on exactly as the untouched one does
        _do(t, op, now + i * 0.7)
        _do(t2, op, now + i * 0.7)
    assert _everything(t) == _everything(t2)


def test_keeping_a_frame_shares_its_lists_until_they_change():
    """The journal keeps a frame per transaction: the copy shares its sets (copying 10 000
    ids a pose cost 314 us), and the first change gives the live frame its own, so the kept
    one still says what was before."""
    frame = Frame({"a", "b"}, {"a"}, Time.of(1), False)
    kept = copy.copy(frame)
    assert kept.tracked is frame.tracked and kept.facing is frame.facing
    frame.update("a", True)  # nothing changes: still shared
    assert kept.tracked is frame.tracked and not frame.dirty
    frame.update("b", True)
    assert (frame.facing, frame.dirty) == ({"a", "b"}, True)
    assert (kept.tracked, kept.facing) == ({"a", "b"}, {"a"})
    kept_again = copy.copy(frame)
    frame.discard("a")
    assert (frame.tracked, frame.facing) == ({"b"}, {"b"})
    assert (kept_again.tracked, kept_again.facing) == ({"a", "b"}, {"a", "b"})


def test_a_tracker_whose_clock_starts_over_is_followed_after_three_poses_in_a_row():
    """A tracker restarts and reuses its ids, its stamps starting over. Three
    poses in a row, each more than RESTART_GAP_S older than the body's last and newer
    than the one before, are its new clock: the caller gets them back as ``restarted``
    (it loses the body, then ingests them anew)."""
    from facing_service.core.tracker import RESTART_EVIDENCE

    t = tracker()
    t.ingest([sample(sec=1000)], now=0.0)
    for i in range(RESTART_EVIDENCE - 1):
        refused = t.ingest([sample(sec=1 + i)], now=0.1 * i)
        assert refused.out_of_order and not refused.restarted and not refused.results
    third = t.ingest([sample(sec=RESTART_EVIDENCE), sample(sec=RESTART_EVIDENCE + 1)], now=1)
    assert [s.pose.stamp for s in third.restarted] == [Time.of(3), Time.of(4)]
    assert not third.out_of_order and not third.results
    lost = t.lose([BodyRef(frame_id="cam", body_id="a")], now=1.0, time_went_back=True)
    assert lost.lost == [BodyRef(frame_id="cam", body_id="a")]
    anew = t.ingest(third.restarted, now=1.0)
    assert [s.stamp for s in anew.results] == [Time.of(3), Time.of(4)] and len(t) == 1


@pytest.mark.parametrize(
    "stream",
    [
        [1, 1, 1, 1, 1],  # one stale pose, re-sent: never newer than the one before
        [5, 3, 4, 2, 6],  # stale poses out of order
        [999.5, 999.6, 999.7, 999.8],  # late by less than the gap: reordered traffic
    ],
)
def test_stale_or_reordered_poses_never_restart_a_body(stream):
    t = tracker()
    t.ingest([sample(sec=1000)], now=0.0)
    for i, sec in enumerate(stream):
        whole, frac = int(sec), round((sec % 1) * 1e9)
        changes = t.ingest([sample(sec=whole, nanosec=frac)], now=0.1 * i)
        assert changes.out_of_order and not changes.restarted
    assert t.states()[0].stamp == Time.of(1000)


def test_an_accepted_pose_between_breaks_the_evidence():
    """The live tracker still sending: a stray old stream interleaved with it never adds
    up to three in a row."""
    t = tracker()
    t.ingest([sample(sec=1000)], now=0.0)
    for i in range(10):
        assert t.ingest([sample(sec=1 + i)], now=i).out_of_order
        assert t.ingest([sample(sec=1001 + i)], now=i).results
    assert t.states()[0].stamp == Time.of(1010)


def test_a_deleted_body_whose_tracker_restarts_comes_back_on_its_new_clock():
    """A clean stop (DELETE: a tombstone refuses older poses for TOMBSTONE_S), then the
    restarted tracker's clock from zero: back after three poses, not after 30 s."""
    t = tracker()
    t.ingest([sample(sec=1000)], now=0.0)
    t.lose([BodyRef(frame_id="cam", body_id="a")], now=0.1)
    assert t.ingest([sample(sec=1)], now=0.2).out_of_order
    assert t.ingest([sample(sec=2)], now=0.3).out_of_order
    back = t.ingest([sample(sec=3)], now=0.4)
    assert [s.pose.stamp for s in back.restarted] == [Time.of(3)]
    assert t.ingest(back.restarted, now=0.4).results
