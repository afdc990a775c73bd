"""Which candidate o-space centres to open, and who joins which: GCFF's energy (each
person's unary cost at a centre plus a fixed cost per centre opened) minimised exactly,
the same whatever order people come in or what they are called.

With no pairwise terms, GCFF's energy is the facility-location problem. GCFF lowers it by
alpha-expansion, which moves many people at once but may stop short of the lowest; a
greedy pass (closing one label at a time) stopped shorter still, keeping pairs where the
lowest energy is a ring (GDet's rings of four to six). Here it is solved exactly, in
two steps:

- **Apart.** Nobody pays more at a centre than at their cheapest plus the cost of a
  label: opening their cheapest would be lower. So a person only ever joins a centre
  within ``mdl`` of their cheapest, and people who share no such centre, even through
  others, are independent problems (in a room, each conversation and its neighbours).
- **Every set.** Each independent part of up to ``MAX_EXACT`` centres is solved by
  trying every set of open centres (``2**k`` sets, built one centre at a time in numpy:
  each set's costs are a smaller set's with one centre more). A part with more (a packed
  crowd all within reach of each other) falls back to greedy closing, the way it was
  solved before: its energy is not the lowest there, and is counted
  (``benchmarks.groups.exact``).

Ties never read the order people are listed in: of sets as low (within ``TIE``: the
same sums taken in another order differ in their last bits), the fewest centres, then
the lowest ranks (``place_rank``: each centre's place); each person then takes their
cheapest open centre, ties to the lowest rank.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Costs (the unit squared) this close are equal.
TIE = 1e-9
#: The most centres of one independent part solved by trying every set of them (2**14
#: sets: about a millisecond); more, and the part is solved greedily.
MAX_EXACT = 14


def assign(unary: FloatArray, mdl: float, rank: IntArray) -> IntArray:
    """Facility location: labels (column indices) minimising the sum of ``unary`` costs
    (people by candidate centres) plus ``mdl`` per label used: GCFF's energy. ``rank``:
    each centre's place, the tie-break that reads no names."""
    labels = np.empty(len(unary), dtype=np.int64)
    for people, cols in independent(unary, mdl):
        if len(cols) == 1:  # one centre they all might join: nothing to choose
            labels[people] = cols[0]
            continue
        part = unary[np.ix_(people, cols)]
        solve = lowest if len(cols) <= MAX_EXACT else greedy
        labels[people] = take(part, solve(part, mdl, rank[cols]), rank[cols], cols)
    return labels


def take(unary: FloatArray, opened: IntArray, rank: IntArray, cols: IntArray) -> IntArray:
    """Each person's label once ``opened`` columns are open: their cheapest, ties to the
    lowest ``rank``; ``cols``: the label each column stands for."""
    result: IntArray = cols[opened][_cheapest(unary[:, opened], rank[opened])]
    return result


def independent(unary: FloatArray, mdl: float) -> list[tuple[IntArray, IntArray]]:
    """The problem's independent parts: each a set of people and the centres any of them
    might join (within ``mdl`` of their cheapest); no centre is in two parts."""
    n = len(unary)
    usable = unary <= unary.min(axis=1, keepdims=True) + mdl + TIE
    shared = (usable.astype(np.int32) @ usable.T.astype(np.int32)) > 0  # (n, n)
    part = np.arange(n)
    while True:  # each person takes the least index it reaches: one per part, at the end
        reached = np.where(shared, part[None, :], n).min(axis=1)
        if np.array_equal(reached, part):
            break
        part = reached
    order = np.argsort(part, kind="stable")
    split = np.flatnonzero(np.diff(part[order])) + 1
    return [
        (people, np.flatnonzero(usable[people].any(axis=0)))
        for people in np.split(order.astype(np.int64), split)
    ]


def lowest(unary: FloatArray, mdl: float, rank: IntArray) -> IntArray:
    """The open columns of least energy, every set of them tried (``2**k`` for ``k``
    columns; ``k`` small); of sets as low, the fewest, then the lowest ranks."""
    n, k = unary.shape
    cheapest = np.empty((n, 1 << k))  # [person, set]: what they pay at its cheapest
    cheapest[:, 0] = np.inf
    size = np.zeros(1 << k, dtype=np.int64)
    for b in range(k):  # the sets with centre b as their highest: a smaller set plus b
        np.minimum(cheapest[:, : 1 << b], unary[:, b : b + 1], out=cheapest[:, 1 << b : 2 << b])
        size[1 << b : 2 << b] = size[: 1 << b] + 1
    energy = cheapest.sum(axis=0) + mdl * size
    tied = np.flatnonzero(energy <= energy.min() + TIE)
    chosen = min(tied.tolist(), key=lambda s: (size[s], sorted(rank[_bits(s, k)].tolist())))
    return _bits(chosen, k)


def _bits(subset: int, k: int) -> IntArray:
    """The columns in ``subset`` (a bit set over ``k`` columns)."""
    return np.flatnonzero((subset >> np.arange(k)) & 1).astype(np.int64)


def greedy(unary: FloatArray, mdl: float, rank: IntArray) -> IntArray:
    """The open columns greedy closing leaves, from every column open: close the one whose
    closing saves most (its ``mdl``, less what its people pay more at their next cheapest
    open column), while one does; of columns saving as much, the one farthest from
    everyone (each person's cost capped at ``mdl``: only those who might join count), then
    the lowest ``rank``. Not the lowest energy: for a part too large for ``lowest``."""
    n, m = unary.shape
    open_ = np.ones(m, dtype=bool)
    rows = np.arange(n)
    while open_.sum() > 1:
        costs = np.where(open_[None, :], unary, np.inf)
        best = _cheapest(costs, rank)  # the cheapest and the next: a partition, no sort
        extra = np.partition(costs, 1, axis=1)[:, 1] - costs[rows, best]
        loss = np.bincount(best, weights=extra, minlength=m)
        gain = np.where(open_, mdl - loss, -np.inf)
        most = gain.max()
        if most <= TIE:
            break
        tied = np.flatnonzero(gain >= most - TIE)
        if len(tied) > 1:
            far = np.minimum(unary[:, tied], mdl).sum(axis=0)
            tied = tied[far >= far.max() - TIE]
        open_[tied[np.argmin(rank[tied])]] = False
    return np.flatnonzero(open_).astype(np.int64)


def _cheapest(costs: FloatArray, rank: IntArray) -> IntArray:
    """Each row's cheapest column, ties (within ``TIE``) to the lowest ``rank``."""
    low = costs.min(axis=1, keepdims=True)
    tied = costs <= low + TIE
    if tied.sum() == len(costs):  # no row has two: the plain argmin
        plain: IntArray = np.argmax(tied, axis=1)
        return plain
    result: IntArray = np.argmin(np.where(tied, rank[None, :], rank.max() + 1), axis=1)
    return result


def place_order(points: FloatArray) -> IntArray:
    """The points' indices in (x, y) order: the same people in the same order whatever
    order they come in (equal points, interchangeable, in the order given)."""
    order: IntArray = np.lexsort((points[:, 1], points[:, 0]))
    return order


def place_rank(points: FloatArray) -> IntArray:
    """Each point's rank in (x, y) order (``place_order``'s inverse): a tie-break that is
    the same whatever order the points come in."""
    order = place_order(points)
    rank = np.empty(len(points), dtype=np.int64)
    rank[order] = np.arange(len(points))
    return rank
