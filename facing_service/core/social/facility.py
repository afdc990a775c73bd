"""Which candidate o-space centres to open, and who joins which: GCFF's energy (each
person's unary cost at a centre plus a fixed cost per centre opened) minimised, the same
whatever order people come in or what they are called.

With no pairwise terms, GCFF's energy is the facility-location problem. GCFF solves it by
alpha-expansion; here by greedy closing, whose ties decide more than they seem: the two
votes of the nearest pair always save as much closed, and the one kept decides who else
joins. Those ties went by index, so by the order people were listed in (and, through the
service's listing, by what they were called). Now a tie goes to the energy's side: the
label closed is the one farther from everyone, the one kept can serve more; then by place
(``place_rank``), never by index. Costs within ``TIE`` of each other are equal (the same
sums taken in another order differ in their last bits).

Compared on small random rooms against every subset of centres and on the shared streams
(docs/groups.md): a local search after the pass (single opens, closes and swaps) and
trying each tied label to its end both reach the lowest energy more often, and neither
groups better (the method's parameters were chosen with this pass); the second costs 3.4
times the scene. Not shipped.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Costs (the unit squared) this close are equal.
TIE = 1e-9


def assign(unary: FloatArray, mdl: float, rank: IntArray) -> IntArray:
    """Facility location: labels minimising the sum of unary costs plus ``mdl`` per label
    used (GCFF's energy). Greedy, from every label open: close the label whose closing
    saves most (its ``mdl``, less what its people pay more at their next cheapest open
    label), while one does; of labels saving as much, the one farthest from everyone
    (each person's cost capped at ``mdl``: only those who might join count), then the
    lowest ``rank``. Then everyone takes their cheapest open label, ties to the lowest
    ``rank`` (its centre's place)."""
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
    cols = np.flatnonzero(open_)
    chosen: IntArray = cols[_cheapest(unary[:, cols], rank[cols])].astype(np.int64)
    return chosen


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
