"""Who is lost when, over time: the input's silence and each person's own (core.silence),
driven as the worker drives it (ingest, heard, look, the timed calls), on sequences."""

from __future__ import annotations

import bisect
import itertools
from dataclasses import dataclass, field

from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, precondition, rule

from facing_service.core.silence import Change, InputSilence, SilenceParams
from facing_service.core.tracker import Tracker

from trackers import sample, tracker

PARAMS = SilenceParams(after_s=1.0, hold_s=10.0, stale_s=2.0, settle_s=0.25)


class Turns:
    """The worker's turn, over a real tracker and a real silence: what arrived (poses of
    people, or something whole that is no pose: a DELETE of nobody, another frame's
    pose), then the input heard, then what time makes due."""

    def __init__(self, params: SilenceParams = PARAMS) -> None:
        self.silence = InputSilence(params)
        self.tracker: Tracker = tracker(stale_after_s=params.stale_s)
        self.said: list[Change] = []
        self._stamp = 0

    def turn(self, now: float, people: list[str] = (), *, other: bool = False) -> set[str]:
        """One turn at ``now``: ``people``'s poses (and ``other``, something whole that is
        nobody's pose); the ids lost in it."""
        lost: set[str] = set()
        if people:
            self._stamp += 1
            self.tracker.ingest([sample(p, sec=self._stamp) for p in people], now)
        if (people or other) and (change := self.silence.heard(now)) is not None:
            self.said.append(change)
        if (change := self.silence.look(now, len(self.tracker) > 0)) is not None:
            self.said.append(change)
        staleness = self.silence.staleness_s(now)
        for call in self.tracker.timed(now, staleness, advancing=not self.silence.holding):
            lost |= {b.body_id for b in call().lost}
        return lost

    def tracked(self) -> set[str]:
        return {s.body_id for s in self.tracker.states()}


def run(events: list[tuple[float, list[str]]], until: float, step: float = 0.125) -> dict:
    """Each person's first loss time, with a turn every ``step`` and at each event."""
    turns, lost = Turns(), {}
    times = sorted({t for t, _ in events} | {i * step for i in range(int(until / step) + 1)})
    by_time: dict[float, list[str]] = {}
    for t, who in events:
        by_time.setdefault(t, []).extend(who)
    for t in times:
        for person in turns.turn(t, by_time.get(t, [])):
            lost.setdefault(person, t)
    return lost


def test_a_person_who_stops_while_another_arrives_every_3_s_is_lost_within_3_5_s():
    """Before: P was never lost (each 3 s gap was a silence, and the hold shifted P's
    time again, every time); now P is lost once Q is heard without it, after the backlog
    has had its moment."""
    events = [(i / 32, ["P", "Q"] if i % 96 == 0 else ["P"]) for i in range(96)]
    events += [(3.0 * k, ["Q"]) for k in range(1, 9)]
    lost = run(events, until=24.0)
    assert 3.0 < lost["P"] - 95 / 32 <= 3.5
    assert lost["Q"] == 2.0  # (while P streamed: its own 3 s pauses, the input heard)


def test_with_the_other_at_30_hz_a_person_who_stops_is_lost_at_the_staleness():
    events = [(i / 32, ["P", "Q"] if i < 96 else ["Q"]) for i in range(24 * 32)]
    lost = run(events, until=24.0, step=1 / 32)
    assert lost["P"] - 95 / 32 == 2.0 and "Q" not in lost


def test_refused_samples_are_not_the_input_and_nobody_is_held_past_the_bound():
    """Five people stop; 4 s later junk arrives (refused: never heard). Before, it read as
    the input back and they were lost 14 s after their last pose; now at the bound."""
    turns = Turns()
    for i in range(30):
        turns.turn(i / 10, ["a", "b", "c", "d", "e"])
    lost_at = {}
    t = 2.9
    while t < 20:
        t = round(t + 0.125, 3)
        for person in turns.turn(t):  # the junk: refused by the input, nothing whole
            lost_at.setdefault(person, t)
    assert set(lost_at) == set("abcde")
    assert all(10.0 <= when - 2.9 <= 10.125 for when in lost_at.values())


def test_a_1_hz_tracker_holds_its_people_and_is_said_slow_once():
    turns = Turns()
    lost: set[str] = set()
    for i in range(24 * 8):
        t = i / 8
        lost |= turns.turn(t, ["a", "b"] if i % 8 == 0 else [])
    assert not lost and turns.tracked() == {"a", "b"}
    assert turns.said == [Change.SLOW]


def test_a_stall_with_its_backlog_loses_nobody_and_a_dead_input_is_held_to_the_bound():
    turns = Turns()
    for i in range(30):
        turns.turn(i / 32, ["a", "b"])
    stall_end = 29 / 32 + 4.0
    for t in (1.5, 2.5, 3.5, 4.5):
        assert turns.turn(t) == set()
    assert turns.turn(stall_end, ["a"]) == set()  # the backlog's first part: a
    assert turns.turn(stall_end + 0.01, ["b"]) == set()  # then b, a moment after
    assert turns.said == [Change.SILENT, Change.BACK]
    assert turns.turn(stall_end + 9.99) == set()
    assert turns.turn(stall_end + 10.01) == {"a", "b"}  # then the tracker died


def test_a_hold_below_the_staleness_never_loses_anyone_early():
    turns = Turns(SilenceParams(after_s=1.0, hold_s=0.5, stale_s=2.0))
    turns.turn(0.0, ["a"])
    assert turns.turn(1.9) == set() and turns.turn(2.0) == {"a"}


# -- sequences against a reference model ----------------------------------------------


@dataclass
class Reference:
    """The rule, said as plainly as it can be: a person is lost once its own poses have
    stopped for the staleness in force, which is ``stale_s`` unless the input is silent
    (nothing heard within ``after_s``) or just back (within ``settle_s`` of the end of a
    gap of ``after_s`` or more), when it is ``max(stale_s, hold_s)`` (hold 0: never)."""

    params: SilenceParams
    heard: list[float] = field(default_factory=list)  # every time the input was heard
    seen: dict[str, float] = field(default_factory=dict)  # present people: own last pose

    def staleness(self, now: float) -> float:
        p, h = self.params, self.heard
        if not h or p.hold_s <= 0:
            return p.stale_s
        silent = now - h[-1] >= p.after_s
        settling = any(
            b - a >= p.after_s and b <= now < b + p.settle_s for a, b in itertools.pairwise(h)
        )
        return max(p.stale_s, p.hold_s) if silent or settling else p.stale_s

    def turn(self, now: float, people: list[str], other: bool) -> None:
        for person in people:
            self.seen[person] = now
        if people or other:
            bisect.insort(self.heard, now)
        staleness = self.staleness(now)
        self.seen = {p: t for p, t in self.seen.items() if now - t < staleness}


PEOPLE = st.lists(st.sampled_from(["a", "b", "c", "d"]), max_size=3, unique=True)


class SilenceMachine(RuleBasedStateMachine):
    """Random sequences of what a tracker sends (poses of some people at any rate, pauses
    of any length, stalls, something whole that is nobody's pose, junk that is nothing
    heard) through the real tracker and silence, checked at every turn against the
    reference."""

    @initialize(hold=st.sampled_from([0.0, 1.5, 10.0]), after=st.sampled_from([0.5, 1.0]))
    def start(self, hold: float, after: float) -> None:
        params = SilenceParams(after_s=after, hold_s=hold, stale_s=2.0, settle_s=0.25)
        self.turns = Turns(params)
        self.reference = Reference(params)
        self.now = 0.0

    def _turn(self, wait: int, people: list[str], other: bool = False) -> None:
        self.now += wait / 8  # eighths of a second: exact in binary, as the rule's sums
        self.turns.turn(self.now, people, other=other)
        self.reference.turn(self.now, people, other)

    @rule(wait=st.integers(0, 4), people=PEOPLE)
    def poses(self, wait: int, people: list[str]) -> None:
        self._turn(wait, people)

    @rule(wait=st.integers(1, 120))
    def pause(self, wait: int) -> None:
        """Nothing at all (a stall, a dead tracker, junk refused): only the clock."""
        self._turn(wait, [])

    @rule(wait=st.integers(0, 40))
    def something_whole(self, wait: int) -> None:
        self._turn(wait, [], other=True)

    @precondition(lambda self: bool(self.reference.seen))
    @rule(wait=st.integers(0, 4))
    def backlog(self, wait: int) -> None:
        """Everyone present, at once (a backlog delivered)."""
        self._turn(wait, sorted(self.reference.seen))

    @invariant()
    def the_same_people(self) -> None:
        assert self.turns.tracked() == set(self.reference.seen), (self.now, self.turns.said)

    @invariant()
    def held_never_past_the_bound(self) -> None:
        p = self.reference.params
        longest = max(p.stale_s, p.hold_s)
        assert all(self.now - t < longest for t in self.reference.seen.values())


SilenceMachine.TestCase.settings = settings(max_examples=150, stateful_step_count=60,
                                            deadline=None)  # fmt: skip
test_silence_sequences = SilenceMachine.TestCase
