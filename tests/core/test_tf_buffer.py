"""The TF buffer against ROS's own tf2 BufferCore (Debian's python3-tf2): random trees and
the real recordings, every lookup within 1e-9, the same error kind where tf2 raises."""

from __future__ import annotations

import math
import random

import pytest

from facing_service.core.tf.buffer import TfBuffer
from facing_service.core.tf.errors import (
    ConnectivityError,
    ExtrapolationError,
    InvalidArgumentError,
    LookupError_,
    TfError,
)
from facing_service.core.tf.geometry import RigidTransform

import bags
from oracles import BAGS, oracle, recording_names

S = 1_000_000_000
TF_TOPICS = ("/tf", "/tf_static")


def yaw(deg: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(math.radians(deg) / 2), math.cos(math.radians(deg) / 2))


def tf(x: float = 0.0, y: float = 0.0, z: float = 0.0, q=(0.0, 0.0, 0.0, 1.0)) -> RigidTransform:
    return RigidTransform((x, y, z), q)


# -- unit: the rules, one by one ---------------------------------------------------------


def test_chain_composes_and_inverts():
    b = TfBuffer()
    b.set_transform("base", "cam", 0, tf(1.0, q=yaw(90)), static=True)
    b.set_transform("cam", "body", 5 * S, tf(2.0), static=False)
    t, stamp = b.lookup("base", "body")
    assert stamp == 5 * S  # the latest common time: the only dynamic link's
    assert t.translation == pytest.approx((1.0, 2.0, 0.0))
    back, _ = b.lookup("body", "base")
    assert back.translation == pytest.approx((-2.0, 1.0, 0.0))


def test_interpolates_between_stamps_and_refuses_to_extrapolate():
    b = TfBuffer()
    b.set_transform("base", "body", 1 * S, tf(0.0, q=yaw(0)), static=False)
    b.set_transform("base", "body", 3 * S, tf(2.0, q=yaw(90)), static=False)
    t, _ = b.lookup("base", "body", 2 * S)
    assert t.translation == pytest.approx((1.0, 0.0, 0.0))
    assert t.rotation == pytest.approx(yaw(45))
    with pytest.raises(ExtrapolationError, match="into the future"):
        b.lookup("base", "body", 4 * S)
    with pytest.raises(ExtrapolationError, match="into the past"):
        b.lookup("base", "body", S // 2)


def test_static_transforms_hold_at_every_time():
    b = TfBuffer()
    b.set_transform("base", "cam", 7 * S, tf(1.0), static=True)
    for time in (0, 1, 10**18):
        assert b.lookup("base", "cam", time)[0].translation == (1.0, 0.0, 0.0)


def test_history_is_ten_seconds_behind_the_newest_stamp():
    b = TfBuffer()
    b.set_transform("base", "body", 1 * S, tf(1.0), static=False)
    b.set_transform("base", "body", 5 * S, tf(5.0), static=False)
    assert b.set_transform("base", "body", 12 * S, tf(12.0), static=False) is None
    with pytest.raises(ExtrapolationError):  # 1 s fell out (older than 12 - 10)
        b.lookup("base", "body", 1 * S)
    assert b.lookup("base", "body", 5 * S)[0].translation == (5.0, 0.0, 0.0)
    assert b.set_transform("base", "body", 1 * S, tf(1.0), static=False) == "old_data"
    assert b.set_transform("base", "body", 5 * S, tf(9.0), static=False) == "repeated_data"


@pytest.mark.parametrize(
    ("parent", "child", "transform", "reason"),
    [
        ("a", "a", tf(), "self_transform"),
        ("a", "", tf(), "no_child_frame_id"),
        ("", "b", tf(), "no_frame_id"),
        ("a", "b", tf(math.nan), "nan"),
        ("a", "b", tf(q=(0.0, 0.0, 0.0, math.nan)), "nan"),
        ("a", "b", tf(math.inf), "nan"),
        ("a", "b", tf(q=(0.0, 0.0, 0.0, 1.006)), "denormalized_quaternion"),
        ("a", "b", tf(q=(0.0, 0.0, 0.0, 0.0)), "denormalized_quaternion"),
    ],
)
def test_bad_transforms_are_refused_with_a_reason(parent, child, transform, reason):
    b = TfBuffer()
    assert b.set_transform(parent, child, S, transform, static=False) == reason
    assert not b.has_frame("b")


def test_lookup_errors_are_tf2s_kinds():
    b = TfBuffer()
    b.set_transform("a", "b", S, tf(), static=False)
    b.set_transform("c", "d", S, tf(), static=False)
    with pytest.raises(LookupError_, match='"nope" passed to lookupTransform argument source'):
        b.lookup("a", "nope")
    with pytest.raises(ConnectivityError):
        b.lookup("a", "d")
    with pytest.raises(InvalidArgumentError):
        b.lookup("", "b")
    assert all(issubclass(e, TfError) for e in (LookupError_, ConnectivityError))


def test_parent_chain_follows_latest_parents():
    b = TfBuffer()
    b.set_transform("map", "base", S, tf(), static=False)
    b.set_transform("base", "cam", 0, tf(), static=True)
    b.set_transform("cam", "face_1", S, tf(), static=False)
    assert b.parent_chain("face_1") == ["face_1", "cam", "base", "map"]


# -- differential: ROS's own tf2 as the oracle --------------------------------------------


def ours(ops: list[list]) -> list[dict]:
    b = TfBuffer()
    out: list[dict] = []
    for op in ops:
        if op[0] == "set":
            _, parent, child, stamp, t, q, static = op
            b.set_transform(parent, child, stamp, RigidTransform(tuple(t), tuple(q)), static=static)
            continue
        _, target, source, time = op
        try:
            result, stamp = b.lookup(target, source, time)
        except TfError as error:
            out.append({"error": error.kind})
            continue
        out.append({"t": list(result.translation), "q": list(result.rotation), "stamp": stamp})
    return out


def assert_same(expected: list[dict], got: list[dict], ops: list[list]) -> None:
    lookups = [op for op in ops if op[0] == "lookup"]
    assert len(expected) == len(got) == len(lookups)
    for want, have, op in zip(expected, got, lookups, strict=True):
        context = f"{op} after {len(ops)} ops"
        if "error" in want:
            assert have.get("error") == want["error"], context
            continue
        assert "error" not in have, f"{context}: tf2 answered, we raised {have['error']}"
        assert have["t"] == pytest.approx(want["t"], abs=1e-9), context
        sign = 1.0 if sum(a * b for a, b in zip(have["q"], want["q"], strict=True)) >= 0 else -1.0
        assert [sign * c for c in have["q"]] == pytest.approx(want["q"], abs=1e-9), context
        assert have["stamp"] == want["stamp"], context


def random_scenario(rng: random.Random) -> list[list]:
    """Random trees (reparenting, static and dynamic links, stamps that repeat, interleave
    and span more than the 10 s history), bad inputs, and lookups at 0, at stamps, between
    and outside them."""
    frames = [f"f{i}" for i in range(rng.randint(3, 7))]
    stamps = [
        rng.choice([1, 2, 3, 5, 8, 13, 21]) * S + rng.choice([0, 0, 250_000_000]) for _ in range(8)
    ]
    # Mostly one parent per child (so histories build up and get interpolated), sometimes
    # another one (reparenting), rarely any frame (loops).
    home = {child: rng.choice(frames[: frames.index(child)]) for child in frames[1:]}
    ops: list[list] = []
    for _ in range(rng.randint(10, 40)):
        if rng.random() < 0.6:
            child = rng.choice(frames[1:])
            roll = rng.random()
            parent = (
                home[child]
                if roll < 0.8
                else rng.choice(frames[: frames.index(child)] if roll < 0.97 else frames)
            )
            angle = rng.uniform(-math.pi, math.pi)
            axis = [rng.gauss(0, 1) for _ in range(3)]
            n = math.sqrt(sum(a * a for a in axis)) or 1.0
            q = [a / n * math.sin(angle / 2) for a in axis] + [math.cos(angle / 2)]
            if rng.random() < 0.1:
                q = [c * rng.choice([1.003, 0.997, 1.02]) for c in q]  # inside / outside tolerance
            t = [rng.uniform(-3, 3) for _ in range(3)]
            if rng.random() < 0.03:
                t[rng.randrange(3)] = math.nan
            ops.append(["set", parent, child, rng.choice(stamps), t, q, rng.random() < 0.2])
        else:
            between = rng.choice(stamps) + rng.choice([-S // 3, S // 3, S // 7])
            time = rng.choice([0, 0, rng.choice(stamps), between, between])
            ops.append(["lookup", rng.choice([*frames, "ghost"]), rng.choice(frames), max(0, time)])
    return ops


def test_random_trees_answer_as_tf2_does():
    rng = random.Random(20261122)
    scenarios = [random_scenario(rng) for _ in range(400)]
    for ops, expected in zip(scenarios, oracle(scenarios), strict=True):
        assert_same(expected, ours(ops), ops)


def recording_ops(name: str) -> list[list]:
    """Every transform of a recording in order, with lookups of each face in camera_link
    after each /tf message: at time 0, at the message's own stamp and 20 ms before.

    Stamps are shifted to start near 100 s: tf2_py passes times to tf2 as float seconds,
    which at 1.6e9 s resolve only ~240 ns (it would look up another time than asked);
    tf2's rules only ever compare and subtract stamps, so the shift changes nothing else.
    """
    messages = [
        (topic, msg) for topic, _, _, msg in bags.messages(BAGS / name) if topic in TF_TOPICS
    ]
    base = min(tr.header.stamp.sec for _, msg in messages for tr in msg.transforms) - 100
    ops: list[list] = []
    for topic, msg in messages:
        for tr in msg.transforms:
            stamp = (tr.header.stamp.sec - base) * S + tr.header.stamp.nanosec
            t, q = tr.transform.translation, tr.transform.rotation
            ops.append(
                [
                    "set",
                    tr.header.frame_id,
                    tr.child_frame_id,
                    stamp,
                    [t.x, t.y, t.z],
                    [q.x, q.y, q.z, q.w],
                    topic == "/tf_static",
                ]
            )
            if tr.child_frame_id.startswith("face_"):
                ops.append(["lookup", "camera_link", tr.child_frame_id, 0])
                ops.append(["lookup", "camera_link", tr.child_frame_id, stamp])
                ops.append(["lookup", "camera_link", tr.child_frame_id, stamp - 20_000_000])
    return ops


@pytest.mark.shared_data
@pytest.mark.parametrize("name", recording_names())
def test_the_recordings_answer_as_tf2_does(name):
    ops = recording_ops(name)
    assert sum(op[0] == "lookup" for op in ops) > 100
    (expected,) = oracle([ops])
    assert_same(expected, ours(ops), ops)


def test_descendants_follow_reparenting():
    b = TfBuffer()
    b.set_transform("map", "base", S, tf(), static=False)
    b.set_transform("base", "cam", 0, tf(), static=True)
    b.set_transform("cam", "body_1", S, tf(), static=False)
    assert b.descendants("base") == {"base", "cam", "body_1"}
    b.set_transform("map", "cam", 0, tf(), static=True)  # cam now hangs from map
    assert b.descendants("base") == {"base"} and b.descendants("map") >= {"cam", "body_1"}


def test_a_frames_history_is_capped_whatever_its_stamps():
    """tf2 bounds a frame's history by time only: transforms 1 ns apart (or arriving each
    older than the last) would grow it, and each insert, without bound. The oldest go
    past MAX_CACHE_ENTRIES; the newest and every lookup stay tf2's."""
    from facing_service.core.tf.buffer import TfBuffer
    from facing_service.core.tf.cache import MAX_CACHE_ENTRIES
    from facing_service.core.tf.geometry import RigidTransform

    buffer = TfBuffer()
    one = RigidTransform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    newest = 10**10
    for i in range(MAX_CACHE_ENTRIES + 500):  # each older than the last
        assert buffer.set_transform("base", "x", newest - i, one, static=False) is None
    assert buffer.set_transform("base", "x", newest, one, static=False) == "repeated_data"
    assert buffer.lookup("base", "x", 0)[1] == newest
    assert buffer.lookup("base", "x", newest - 100)[0].translation == (1.0, 0.0, 0.0)
    kept = buffer._caches["x"].items
    assert len(kept) == MAX_CACHE_ENTRIES and kept[-1].stamp == newest - MAX_CACHE_ENTRIES + 1


def test_frames_are_bounded_and_the_gone_forgotten():
    """tf2 never forgets a frame (400 000 names took 517 MB): at most max_frames, room
    made by forgetting dynamic leaves silent for the cache time, else refused."""
    buffer = TfBuffer(max_frames=10)
    for i in range(9):
        assert buffer.set_transform("map", f"f{i}", S, tf(), static=False) is None
    assert buffer.set_transform("map", "f9", S, tf(), static=False) == "too_many_frames"
    assert buffer.set_transform("map", "f0", 12 * S, tf(), static=False) is None  # f0 lives
    assert buffer.set_transform("map", "new", 12 * S, tf(), static=False) is None
    assert buffer.frames() == {"map", "f0", "new"}  # f1..f8 gone: silent for 10 s
    assert buffer.lookup("map", "f0", 0)[1] == 12 * S


def test_stamps_of_a_frame_in_a_window():
    buffer = TfBuffer()
    for sec in (1, 2, 3, 4):
        buffer.set_transform("map", "a", sec * S, tf(), static=False)
    buffer.set_transform("map", "s", 0, tf(), static=True)
    assert buffer.stamps("a", 1 * S, 3 * S) == [2 * S, 3 * S]
    assert buffer.stamps("a", 0, 10 * S) == [S, 2 * S, 3 * S, 4 * S]
    assert buffer.stamps("s", 0, 10 * S) == [] and buffer.stamps("nothing", 0, S) == []
