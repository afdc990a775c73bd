"""What the last seconds say about a frame's people: each person's heading, and each pair
being in one conversation.

A robot sees a stream. A conversation lasts minutes; one reading's heading is noise (an
estimate flickering between neighbours, a tracker's 90-degree steps), and one frame's
grouping follows it. So the grouping said is not the newest frame's, but what the last
seconds show:

- **a person's heading** is the direction of the mean of their recent headings' unit
  vectors, each reading fading with time constant ``heading_s`` (a heading flickering
  between 0 and 90 degrees is read as the 45 it most likely is; a turn is followed
  within about that long);
- **a pair's evidence of being together** is ``core.evidence``'s accumulation: ``+dt``
  while the frame's grouping (on those headings) puts them in one group, ``-dt`` while it
  does not, held within [0, ``together_s``] (a glance of one second is a quarter of the
  way to a pair; a pair that stood together for long survives ``together_s / 2`` of
  contrary frames, and no more: a member leaving is said within that);
- **the groups** are the people whose pairs, on average, have more than half of the full
  evidence (average linkage), so a group is said whole even where one of its pairs is
  weaker than the rest.

Pure: the caller's clock (seconds) and ids. A person new to the frame starts from their
reading, and undecided with everyone (half the full evidence): with no history, the first
frame decides, as frame by frame; from then on the last seconds do. A pair long apart has
no evidence: seen together, they are said a group after ``together_s / 2``. A person gone
is forgotten.

Place is read as it comes: a tracker's position is not noise at the scale of a group (a
heading's 90-degree step is), and the grouping of each reading already weighs it; a
memory of places would only follow a person walking away later.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..evidence import MAX_GAP_S
from .facility import place_order
from .groups import in_order

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: A pair is together when its share of the full evidence is above this (more often
#: together than not, over the memory).
TOGETHER = 0.5
#: How far the newest frame tips an exact tie (newcomers start undecided, at one half).
TIE = 1e-9
#: A share's tip per metre apart: of pairs as often together, the nearer merge first
#: (less than TIE over the 20 m a scene spans: the newest frame still decides first).
NEARER = 1e-12
#: The memory has settled when no heading is farther than this from its reading (the
#: vectors' distance, about radians) and every pair's evidence is at a bound.
SETTLED = 0.02


@dataclass(frozen=True, slots=True)
class MemoryParams:
    """How long the scene remembers (seconds); 0: the newest reading alone. Defaults:
    chosen with each dataset held out, among the settings that say every change of the
    made streams within 3 s (docs/groups.md, ``python -m benchmarks.groups.stream``)."""

    heading_s: float = 0.5
    together_s: float = 4.0


class SceneMemory:
    """The evidence of one frame's people, between readings.

    Each computation first counts the time since the last one as the last reading's (the
    people stood as last read until now: a scene not worked out for a while, since
    nobody moved, has seen that long of them), then takes the new reading: it weighs
    from the next computation on, a period later while the memory settles."""

    def __init__(self, params: MemoryParams, period_s: float = 0.0) -> None:
        """``period_s``: how often the scene is worked out while the memory settles. A
        step counts at most ``MAX_GAP_S`` (a stall is no evidence) or half again the
        period, whichever is longer: capped at 0.5 s, a scene worked out once a second
        (``--group-rate-hz 1``) said a pair after 4 s of a 4 s memory, at 0.25 Hz 16 s,
        where half the memory is promised."""
        self.params = params
        self._longest_step = max(MAX_GAP_S, 1.5 * period_s)
        self._ids: list[str] = []
        self._facing = np.zeros((0, 2))  # (n, 2): the faded mean of heading unit vectors
        self._readings = np.zeros((0, 2))  # (n, 2): the newest reading's unit vector
        self._together = np.zeros((0, 0))  # (n, n) seconds of evidence, symmetric
        self._was = np.zeros((0, 0))  # (n, n) the last grouping: +1 together, -1 not, 0 new
        self._last: float | None = None
        self._dt = 0.0

    def headings(self, ids: list[str], headings: FloatArray, now: float) -> FloatArray:
        """Each person's heading as the last seconds say it (radians, in ``ids`` order),
        given their reading ``headings`` at ``now``."""
        reading = np.column_stack([np.cos(headings), np.sin(headings)])
        self._align(ids, reading)
        step = 0.0 if self._last is None else max(now - self._last, 0.0)
        self._dt = min(step, self._longest_step)
        self._last = now
        tau = self.params.heading_s
        if tau > 0:
            keep = math.exp(-self._dt / tau)
            self._facing = keep * self._facing + (1 - keep) * self._readings
        else:  # no memory: the newest reading
            self._facing = reading
        self._readings = reading
        still: FloatArray = np.arctan2(self._facing[:, 1], self._facing[:, 0])
        return still

    def groups(self, labels: IntArray, where: FloatArray) -> IntArray:
        """Labels of the groups the last seconds say (``groups.detect``'s form), given
        this reading's grouping ``labels`` and where each person stands (``where``, (n, 2)
        m; both in the order ``headings`` was given). The linkage's ties go to the pair
        standing nearer, then by place: never by the order people are listed in, nor by
        what they are called."""
        together = labels[:, None] == labels[None, :]
        span = self.params.together_s
        self._together = np.clip(self._together + self._was * self._dt, 0.0, span)
        self._was = np.where(together, 1.0, -1.0)
        if span <= 0:
            return labels
        # An exact tie (newcomers, undecided) goes the newest frame's way; the linkage's
        # own ties to the nearer pair, then by place (by id, the same room was
        # grouped otherwise when its people were called otherwise).
        apart = np.hypot(*(where[:, None, :] - where[None, :, :]).transpose(2, 0, 1))
        share = self._together / span + self._was * TIE - NEARER * apart
        order = place_order(where)
        out = np.empty(len(order), dtype=np.int64)
        out[order] = linked(share[np.ix_(order, order)], TOGETHER)
        return in_order(out)

    @property
    def settled(self) -> bool:
        """Whether time alone would change nothing: every heading at its reading and every
        pair's evidence at the bound its last grouping pushes it to. While it has not, the
        scene is worked out again though nobody moves."""
        if len(self._ids) == 0:
            return True
        span = self.params.together_s
        off = np.hypot(*(self._facing - self._readings).T)
        if off.max() > SETTLED:
            return False
        bound = np.where(self._was > 0, span, 0.0)
        return span <= 0 or bool(np.all(np.abs(self._together - bound) <= 1e-9))

    def _align(self, ids: list[str], reading: FloatArray) -> None:
        """Carry what is known of each person in ``ids`` over to its new place; forget
        those gone; newcomers as their reading, undecided with everyone."""
        if ids == self._ids:
            return
        n = len(ids)
        old = {person: i for i, person in enumerate(self._ids)}
        kept = np.array([old.get(person, -1) for person in ids], dtype=np.int64)
        known = kept >= 0
        facing, readings = reading.copy(), reading.copy()
        facing[known] = self._facing[kept[known]]
        readings[known] = self._readings[kept[known]]
        together = np.full((n, n), self.params.together_s * TOGETHER)  # undecided
        was = np.zeros((n, n))
        both = np.ix_(np.flatnonzero(known), np.flatnonzero(known))
        together[both] = self._together[np.ix_(kept[known], kept[known])]
        was[both] = self._was[np.ix_(kept[known], kept[known])]
        self._ids, self._facing, self._readings = ids, facing, readings
        self._together, self._was = together, was


def linked(share: FloatArray, above: float) -> IntArray:
    """Average linkage: clusters merged, the closest first, while some two clusters' pairs
    have a mean share above ``above``; labels in order of first member. Only people with
    some pair above it can ever merge (a mean above needs one): the rest stay alone, and
    the loop runs on the few who can."""
    n = len(share)
    labels = np.arange(n, dtype=np.int64)
    off = share - np.diag(np.diag(share))
    can = np.flatnonzero((off > above).any(axis=1))
    if len(can) > 1:
        labels[can] = can[_linkage(off[np.ix_(can, can)], above)]
    return in_order(labels)


def _linkage(sums: FloatArray, above: float) -> IntArray:
    """``linked``'s loop on people who may merge: each one's cluster (a member's index)."""
    sums = sums.copy()  # between clusters: the sum over their pairs
    n = len(sums)
    labels = np.arange(n, dtype=np.int64)
    size = np.ones(n)
    alive = np.ones(n, dtype=bool)
    while True:
        mean = sums / np.outer(size, size)
        mean[~alive, :] = -np.inf
        mean[:, ~alive] = -np.inf
        np.fill_diagonal(mean, -np.inf)
        a, b = np.unravel_index(int(np.argmax(mean)), mean.shape)
        if mean[a, b] <= above:
            return labels
        sums[a, :] += sums[b, :]
        sums[:, a] += sums[:, b]
        sums[a, a] = 0.0
        size[a] += size[b]
        alive[b] = False
        labels[labels == b] = a
