"""F-formations: which people (and is the robot one of them) stand in one conversation.

Pure numpy over positions and headings in one base frame, in metres and radians.

The method is GCFF's (Setti, Russell, Bassetti, Cristani, PLOS ONE 2015; franzsetti/GCFF
``gc.m``, MIT) with one change that lets one parameter set serve rooms of any spacing.
GCFF: each person votes for the centre of their o-space a fixed stride in front of them;
people are assigned to groups minimising the squared distance of their vote to their
group's centre plus a fixed cost per group (the minimum description length, ``mdl``)
plus a penalty for a member hidden behind another member as seen from the centre;
centres are refitted as their members' mean, and the assignment is solved again until
it settles. Here a person's vote is not a point but a **segment** in front of them,
from ``near_m`` to ``far_m``: the o-space of two people a metre apart is half a metre in
front of each, that of six people in a ring farther, and the distance of a centre to the
segment does not care which. (GCFF's stride is the degenerate segment ``near = far``.)

The assignment is GCFF's energy (unary costs plus a cost per label) minimised by greedy
label removal and reassignment rather than alpha-expansion: with no pairwise terms that
is the facility-location problem, and for the tens of people in one frame the greedy
pass with a final reassignment reaches GCFF's solutions (``benchmarks/groups.py``).

GCFF's visibility penalty is kept, in its units: ``100 ** (cos * d_k / d_j)`` cm² when
member k stands behind member j (cosine of the angle between them, from the centre,
above 0.75), here converted to m² (the same penalty, 1e-4 times the number).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: GCFF's visibility rule: the cosine above which one member hides another, and the
#: penalty's base (its own units, cm², converted here).
HIDDEN_COS = 0.75
CM2_TO_M2 = 1e-4
MAX_ITERATIONS = 10
CENTRE_REFITS = 5  # fixed-point steps when refitting a centre to its members' votes
MAX_EXPONENT = 6.0  # the penalty's exponent is capped (100**6 cm² = 1e8 m²: out either way)


@dataclass(frozen=True, slots=True)
class GroupParams:
    near_m: float = 0.5  # a person's o-space vote starts this far in front of them
    far_m: float = 0.5  # ... and ends here (GCFF: near = far, its stride)
    mdl_m2: float = 0.6  # the cost of one more group (GCFF's MDL, in m²)
    spread_deg: float = 0.0  # the vote's sector either side of the heading (0: a segment)


@dataclass(frozen=True, slots=True)
class Votes:
    """Each person's vote for their o-space centre: the sector in front of them from
    ``near`` to ``far``, ``spread`` (radians) either side of their heading."""

    positions: FloatArray  # (n, 2)
    headings: FloatArray  # (n,)
    near: float
    far: float
    spread: float

    def closest(self, points: FloatArray, person: IntArray | None = None) -> FloatArray:
        """The closest point of every person's sector to every point ((m, 2) -> (m, n,
        2)), or, with ``person`` (one index per point), of that person's sector only
        ((m, 2) -> (m, 2))."""
        pos, head = self.positions, self.headings
        if self.near == self.far and self.spread == 0:  # GCFF's point votes: no geometry
            point = pos + self.near * np.column_stack([np.cos(head), np.sin(head)])
            if person is None:
                return np.broadcast_to(point, (len(points), *point.shape))
            return point[person]
        if person is None:
            rel = points[:, None, :] - pos[None, :, :]  # (m, n, 2)
            heading = head[None, :]
        else:
            rel = points - pos[person]
            heading = head[person]
        rho = np.hypot(rel[..., 0], rel[..., 1])
        off = np.angle(np.exp(1j * (np.arctan2(rel[..., 1], rel[..., 0]) - heading)))
        turn = np.clip(off, -self.spread, self.spread)
        r = np.clip(rho * np.cos(off - turn), self.near, self.far)
        phi = heading + turn
        base = pos[None, :, :] if person is None else pos[person]
        return base + np.stack([r * np.cos(phi), r * np.sin(phi)], axis=-1)


def _unary(votes: Votes, centres: FloatArray, mdl: float) -> FloatArray:
    """(n, m): the squared distance of each person's vote to each centre, plus GCFF's
    visibility penalty (m²) among the people near that centre: one farther from it than
    another in about the same direction is penalised, the more the farther behind."""
    gap = votes.closest(centres) - centres[:, None, :]  # (m, n, 2)
    cost = np.einsum("mnj,mnj->mn", gap, gap)  # (m, n)
    disp = votes.positions[None, :, :] - centres[:, None, :]  # (m, n, 2)
    dist = np.maximum(np.hypot(disp[..., 0], disp[..., 1]), 1e-9)  # (m, n)
    cos = np.einsum("mkj,mlj->mkl", disp, disp) / (dist[:, :, None] * dist[:, None, :])
    ratio = dist[:, :, None] / dist[:, None, :]  # [m, k, l] > 1: k is behind l
    near = cost < mdl
    behind = (ratio > 1.0) & (cos > HIDDEN_COS) & near[:, :, None] & near[:, None, :]
    exponent = np.where(behind, np.minimum(cos * ratio, MAX_EXPONENT), 0.0)
    penalty = np.where(behind, np.power(100.0, exponent), 0.0).sum(axis=2) * CM2_TO_M2
    return (cost + penalty).T


def _assign(unary: FloatArray, mdl: float) -> IntArray:
    """Facility location: labels minimising the sum of unary costs plus ``mdl`` per label
    used. Greedy: from every label open, close the one whose closing saves most (its
    ``mdl``, less what its people pay more at their next cheapest open label), while one
    does; then everyone takes their cheapest open label."""
    n, m = unary.shape
    open_ = np.ones(m, dtype=bool)
    rows = np.arange(n)
    while open_.sum() > 1:
        costs = np.where(open_[None, :], unary, np.inf)
        order = np.argsort(costs, axis=1)
        best, second = order[:, 0], order[:, 1]
        extra = costs[rows, second] - costs[rows, best]
        loss = np.bincount(best, weights=extra, minlength=m)
        gain = np.where(open_, mdl - loss, -np.inf)
        k = int(np.argmax(gain))
        if gain[k] <= 0:
            break
        open_[k] = False
    cols = np.flatnonzero(open_)
    return cols[np.argmin(unary[:, cols], axis=1)].astype(np.int64)


def _refit(votes: Votes, labels: IntArray) -> FloatArray:
    """Each label's centre: the point nearest (least squares) its members' votes, by a
    few fixed-point steps from the mean of the votes' middles."""
    count = np.bincount(labels).astype(np.float64)[:, None]

    def mean_by_label(points: FloatArray) -> FloatArray:
        sums = [np.bincount(labels, weights=points[:, j], minlength=len(count)) for j in (0, 1)]
        return np.column_stack(sums) / count

    middle = (votes.near + votes.far) / 2.0
    facing = np.column_stack([np.cos(votes.headings), np.sin(votes.headings)])
    centres = mean_by_label(votes.positions + middle * facing)
    if votes.near == votes.far and votes.spread == 0:
        return centres  # points (GCFF's stride): the mean is the least-squares centre
    for _ in range(CENTRE_REFITS):
        centres = mean_by_label(votes.closest(centres[labels], labels))
    return centres


def detect(positions: FloatArray, headings: FloatArray, p: GroupParams) -> IntArray:
    """A group label per person (0..G-1, in order of first member); a label held by one
    person is a singleton, not a group (``groups`` leaves those out)."""
    n = len(positions)
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    votes = Votes(positions, headings, p.near_m, p.far_m, np.radians(p.spread_deg))
    labels = np.arange(n, dtype=np.int64)
    centres = _refit(votes, labels)
    for _ in range(MAX_ITERATIONS):
        new = _assign(_unary(votes, centres, p.mdl_m2), p.mdl_m2)
        _, new = np.unique(new, return_inverse=True)
        centres = _refit(votes, new)
        if np.array_equal(new, labels):
            break
        labels = new
    return _in_order(labels)


def _in_order(labels: IntArray) -> IntArray:
    """Labels renumbered in order of their first member (stable for equal inputs)."""
    first: dict[int, int] = {}
    return np.array([first.setdefault(int(x), len(first)) for x in labels], dtype=np.int64)


def groups(labels: IntArray) -> list[list[int]]:
    """The groups (two or more members), as lists of indices."""
    out: dict[int, list[int]] = {}
    for i, label in enumerate(labels.tolist()):
        out.setdefault(label, []).append(i)
    return [members for members in out.values() if len(members) > 1]


@dataclass(frozen=True, slots=True)
class Group:
    """A group as said: a stable id, its members, whether the robot is one, its centre."""

    id: int
    members: frozenset[str]
    robot: bool
    centre: tuple[float, float]


class GroupTracker:
    """Stable group ids over time, without flicker. Pure: the caller's clock.

    A grouping (the partition ``detect`` finds) is said only once it has held
    ``hold_s``: a person's heading flickering across the threshold between two readings
    does not make groups flicker (as hysteresis keeps facing calm). A group that keeps at
    least half of its members keeps its id; a new one gets the next id; a group gone is
    said dissolved. Singletons are not groups; the robot (``ROBOT``) is a member like any
    other, and a group with it says ``robot``."""

    ROBOT = ""  # REP 155: the robot's id in hri_msgs/Gaze and Group is the empty string

    def __init__(self, hold_s: float) -> None:
        self.hold_s = hold_s
        self.groups: dict[int, Group] = {}
        self._next_id = 1
        self._candidate: frozenset[frozenset[str]] | None = None
        self._since = 0.0

    def update(
        self, found: list[tuple[frozenset[str], tuple[float, float]]], now: float
    ) -> tuple[list[Group], list[int]]:
        """The groups ``detect`` found now (members, centre); what changed: the groups
        formed or changed, and the ids dissolved (both empty while nothing changed)."""
        partition = frozenset(members for members, _ in found if len(members) > 1)
        if partition != self._candidate:
            self._candidate, self._since = partition, now
        said = frozenset(g.members for g in self.groups.values())
        if partition == said or now - self._since < self.hold_s:
            self._recentre(found)
            return [], []
        return self._adopt(found)

    def _recentre(self, found: list[tuple[frozenset[str], tuple[float, float]]]) -> None:
        by_members = dict(found)
        for gid, group in self.groups.items():
            if (centre := by_members.get(group.members)) is not None:
                self.groups[gid] = Group(gid, group.members, group.robot, centre)

    def _adopt(
        self, found: list[tuple[frozenset[str], tuple[float, float]]]
    ) -> tuple[list[Group], list[int]]:
        old = dict(self.groups)
        new: dict[int, Group] = {}
        # Most overlap first: the group that keeps most of an old group's members keeps its id.
        pairs = sorted(
            (
                (len(members & g.members), gid, i)
                for i, (members, _) in enumerate(found)
                for gid, g in old.items()
                if len(members) > 1 and 2 * len(members & g.members) >= len(g.members)
            ),
            reverse=True,
        )
        taken: dict[int, int] = {}  # found index -> id
        for _, gid, i in pairs:
            if i not in taken and gid not in taken.values():
                taken[i] = gid
        changed = []
        for i, (members, centre) in enumerate(found):
            if len(members) < 2:
                continue
            gid = taken.get(i)
            if gid is None:
                gid, self._next_id = self._next_id, self._next_id + 1
            group = Group(gid, members, self.ROBOT in members, centre)
            new[gid] = group
            if gid not in old or old[gid].members != members:
                changed.append(group)
        self.groups = new
        return changed, sorted(old.keys() - new.keys())
