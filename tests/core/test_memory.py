"""What the last seconds say about a frame's people (core.social.memory): a
heading is the fading mean of its readings, a pair's being together accumulates and
decays, and the groups are the people whose pairs are on average together."""

from __future__ import annotations

import math

import numpy as np
import pytest

from facing_service.core.social.memory import MemoryParams, SceneMemory, linked

DT = 0.1


def in_a_row(n: int) -> np.ndarray:
    """(n, 2): places a metre apart along x, in listing order."""
    return np.column_stack([np.arange(n, dtype=np.float64), np.zeros(n)])


def feed(memory: SceneMemory, ids, headings, labels, start: float, seconds: float) -> np.ndarray:
    """The groups after ``seconds`` of the same reading, one every ``DT`` from ``start``."""
    out = np.asarray(labels)
    for k in range(round(seconds / DT)):
        memory.headings(list(ids), np.radians(headings), start + k * DT)
        out = memory.groups(np.asarray(labels, dtype=np.int64), in_a_row(len(labels)))
    return out


def test_a_heading_flickering_between_two_steps_is_read_between_them():
    memory = SceneMemory(MemoryParams(heading_s=1.0, together_s=4.0))
    read = []
    for k in range(100):
        heading = 0.0 if k % 3 else 90.0  # one reading in three the other step
        read.append(memory.headings(["a"], np.radians([heading]), k * DT)[0])
    assert math.degrees(np.mean(read[50:])) == pytest.approx(30.0, abs=8.0)
    assert max(abs(math.degrees(r) - 30.0) for r in read[50:]) < 45.0  # never the 90 step


def test_a_newcomer_is_read_as_their_reading_and_a_turn_is_followed():
    memory = SceneMemory(MemoryParams(heading_s=1.0, together_s=4.0))
    assert memory.headings(["a"], np.radians([0.0]), 0.0)[0] == pytest.approx(0.0)
    assert memory.headings(["a", "b"], np.radians([0.0, 120.0]), 0.1)[1] == pytest.approx(
        math.radians(120.0)
    )
    for k in range(2, 60):
        turned = memory.headings(["a", "b"], np.radians([90.0, 120.0]), k * DT)
    assert math.degrees(turned[0]) == pytest.approx(90.0, abs=1.0)  # 5.8 s: followed


def test_newcomers_are_read_as_their_first_frame_says():
    """No history: undecided, so the first frame decides (as frame by frame would)."""
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0))
    assert feed(memory, "ab", [0, 180], [0, 0], 0.0, 0.1).tolist() == [0, 0]
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0))
    assert feed(memory, "ab", [0, 180], [0, 1], 0.0, 0.1).tolist() == [0, 1]


def test_a_pair_is_said_together_after_half_the_memory_and_a_glance_is_forgotten():
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0))
    feed(memory, "ab", [0, 180], [0, 1], 0.0, 5.0)  # long apart: no evidence
    glance = feed(memory, "ab", [0, 180], [0, 0], 5.0, 1.0)
    assert glance.tolist() == [0, 1]  # a second together: a quarter of the way
    assert feed(memory, "ab", [0, 180], [0, 1], 6.0, 2.0).tolist() == [0, 1]
    assert feed(memory, "ab", [0, 180], [0, 0], 8.0, 1.9).tolist() == [0, 1]
    assert feed(memory, "ab", [0, 180], [0, 0], 9.9, 0.3).tolist() == [0, 0]  # 2.1 s of 4


def test_a_pair_long_together_survives_contrary_frames_for_half_the_memory_and_no_more():
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0))
    feed(memory, "ab", [0, 180], [0, 0], 0.0, 30.0)
    assert feed(memory, "ab", [0, 180], [0, 1], 30.0, 1.9).tolist() == [0, 0]
    assert feed(memory, "ab", [0, 180], [0, 1], 31.9, 0.3).tolist() == [0, 1]


def test_flickering_frames_keep_a_group_whole():
    """A ring of four whose frames split it in two pairs one frame in three: said whole."""
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0))
    for k in range(100):
        labels = [0, 0, 1, 1] if k % 3 == 0 else [0, 0, 0, 0]
        said = memory.headings(list("abcd"), np.zeros(4), k * DT) is not None and memory.groups(
            np.array(labels), in_a_row(4)
        )
    assert said.tolist() == [0, 0, 0, 0]


def test_what_is_known_of_a_person_follows_them_when_others_come_and_go():
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0))
    feed(memory, "ab", [0, 180], [0, 0], 0.0, 10.0)
    # c arrives first in the order, apart: a and b are still a pair, c alone
    now = feed(memory, "cab", [90, 0, 180], [0, 1, 1], 10.0, 3.0)
    assert now.tolist() == [0, 1, 1]
    # a leaves, and b's frame puts them with c for a glance: c's 3 s apart weigh more
    assert feed(memory, "cb", [90, 180], [0, 0], 13.0, 0.5).tolist() == [0, 1]


def test_the_memory_off_says_each_frame_as_it_is():
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=0.0))
    read = memory.headings(list("abc"), np.radians([37.0, 0.0, 0.0]), 0.0)
    assert read[0] == pytest.approx(math.radians(37))
    assert memory.groups(np.array([0, 1, 1]), in_a_row(3)).tolist() == [0, 1, 1]
    assert memory.settled


def test_the_memory_settles_once_time_alone_would_change_nothing():
    memory = SceneMemory(MemoryParams(heading_s=1.0, together_s=4.0))
    feed(memory, "ab", [0, 180], [0, 0], 0.0, 0.5)
    assert not memory.settled  # the pair's evidence still rising (from undecided)
    feed(memory, "ab", [0, 180], [0, 0], 0.5, 4.0)
    assert memory.settled
    memory.headings(["a", "b"], np.radians([90.0, 180.0]), 4.6)
    assert not memory.settled  # a's heading still turning


def test_average_linkage_joins_a_group_whole_and_does_not_chain():
    ring = np.full((4, 4), 0.8)
    ring[0, 2] = ring[2, 0] = 0.3  # one weak pair inside a strong group
    assert linked(ring, 0.5).tolist() == [0, 0, 0, 0]
    chain = np.eye(3)
    chain[0, 1] = chain[1, 0] = chain[1, 2] = chain[2, 1] = 0.6  # a-b and b-c, never a-c
    assert sorted(np.bincount(linked(chain, 0.5)).tolist()) == [1, 2]
    assert linked(np.zeros((0, 0)), 0.5).tolist() == []


@pytest.mark.parametrize("seed", range(5))
def test_the_groups_said_do_not_depend_on_the_order_or_the_names_of_people(seed):
    """A defect found: the linkage's ties went by id, so a room was grouped otherwise when its
    people were called otherwise."""
    rng = np.random.default_rng(seed)
    places = rng.uniform(-3, 3, (8, 2))
    frames = [rng.integers(0, 3, 8) for _ in range(60)]  # each reading's grouping
    said = []
    for order, names in ((np.arange(8), "abcdefgh"), (rng.permutation(8), "hgfedcba")):
        memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0))
        for k, labels in enumerate(frames):
            memory.headings([names[i] for i in order], np.zeros(8), k * DT)
            out = memory.groups(labels[order], places[order])
        said.append({frozenset(int(order[i]) for i in np.flatnonzero(out == g)) for g in set(out)})
    assert said[0] == said[1]


@pytest.mark.parametrize("names", ["abc", "cba", "bac"])
def test_of_two_pairs_as_sure_the_nearer_is_said_whatever_the_names(names):
    """A chain: a-b and b-c as often together (5/8 of the memory), a-c rarely, and the
    newest frame apart: one pair is said, and it is the pair standing nearer (b and c,
    0.8 m apart; a is 1.2 m from b), whatever the people are called."""
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0))
    places = np.array([[0.0, 0.0], [1.2, 0.0], [2.0, 0.0]])
    t, out = 0.0, np.zeros(3, dtype=np.int64)
    for labels, seconds in (([0, 0, 0], 5.0), ([0, 0, 1], 2.0), ([0, 1, 1], 1.0), ([0, 1, 2], 0.5)):
        for _ in range(round(seconds / DT)):
            memory.headings(list(names), np.zeros(3), t)
            out = memory.groups(np.array(labels, dtype=np.int64), places)
            t += DT
    assert out[1] == out[2] != out[0]


@pytest.mark.parametrize("rate_hz", [10.0, 2.0, 1.0, 0.25])
def test_a_pair_is_said_after_half_the_memory_at_any_rate_the_scene_is_worked_out(rate_hz):
    """A defect found: each step was capped at 0.5 s, so below 2 Hz the memory ran slow: a 4 s
    memory said a pair after 2 s at 10 or 2 Hz, 4 s at 1 Hz, 16 s at 0.25 Hz. Now within
    one period of half the memory (the first reading counts from the next computation)."""
    period = 1.0 / rate_hz
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0), period_s=period)
    apart = np.asarray([0, 1], dtype=np.int64)
    together = np.asarray([0, 0], dtype=np.int64)
    t = 0.0
    while t < 10.0:  # long apart: no evidence
        memory.headings(["a", "b"], np.radians([0.0, 180.0]), t)
        memory.groups(apart, in_a_row(2))
        t += period
    started = t
    while True:
        memory.headings(["a", "b"], np.radians([0.0, 180.0]), t)
        if memory.groups(together, in_a_row(2)).tolist() == [0, 0]:
            break
        t += period
        assert t - started < 20.0, "never said"
    assert 2.0 - 1e-9 <= t - started <= 2.0 + period + 1e-9, (rate_hz, t - started)


def test_a_stall_longer_than_the_period_is_no_evidence():
    """What the cap is for: a service that computed nothing for 30 s (a pause) counts
    half again a period of it, not 30 s."""
    memory = SceneMemory(MemoryParams(heading_s=0.0, together_s=4.0), period_s=0.1)
    feed(memory, "ab", [0, 180], [0, 1], 0.0, 5.0)  # long apart: no evidence
    memory.headings(["a", "b"], np.radians([0.0, 180.0]), 5.0)
    memory.groups(np.asarray([0, 0], dtype=np.int64), in_a_row(2))  # together, then a stall
    memory.headings(["a", "b"], np.radians([0.0, 180.0]), 35.0)
    assert memory.groups(np.asarray([0, 0], dtype=np.int64), in_a_row(2)).tolist() == [0, 1]
