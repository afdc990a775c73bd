"""F-formations: which people (and is the robot one of them) stand in one conversation.

Pure numpy over positions and headings in one base frame, in metres and radians.

The method is GCFF's (Setti, Russell, Bassetti, Cristani, PLOS ONE 2015; franzsetti/GCFF
``gc.m``, MIT). GCFF: each person votes for the centre of their o-space a fixed stride in
front of them; people are assigned to groups minimising the squared distance of their vote
to their group's centre plus a fixed cost per group (the minimum description length,
``mdl``) plus a penalty for a member hidden behind another member as seen from the centre;
centres are refitted as their members' mean, and the assignment is solved again until it
settles. Here each person's stride is their own (the o-space is a ring whose
size follows from its people): it reaches the point of their heading as far from the
nearest person ahead (within ``cone_deg``) as from themselves, the centre of a ring both
stand on, kept within ``[stride_min, stride_max]`` (nobody ahead: the least); GCFF's fixed
stride is the case ``stride_min = stride_max``. Lengths are metres by default; with a
``RoomScale`` they are the room's unit (its people's nearest-neighbour spacing), the rule
measured in earlier rounds and not shipped (docs/groups.md).

The assignment is GCFF's energy (unary costs plus a cost per label) at its lowest for
each round's centres (``facility``: with no pairwise terms that is the facility-location
problem, solved exactly where GCFF's alpha-expansion and the greedy pass before it could
stop above it), its ties broken by the energy and by place, never by the order people are
listed in: the same people are grouped alike whatever they are called.

GCFF's visibility penalty is kept, in its units: ``100 ** (cos * d_k / d_j)`` cm² when
member k stands behind member j (cosine of the angle between them, from the centre,
above 0.75), converted to m² (1e-4 times the number), in the room's unit squared.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Set as AbstractSet
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .facility import TIE, assign, place_rank
from .join import JoinPose

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: GCFF's visibility rule: the cosine above which one member hides another, and the
#: penalty's base (its own units, cm², converted here).
HIDDEN_COS = 0.75
CM2_TO_M2 = 1e-4
MAX_ITERATIONS = 10
MAX_EXPONENT = 6.0  # the penalty's exponent is capped (100**6 cm² = 1e8 m²: out either way)


@dataclass(frozen=True, slots=True)
class GroupParams:
    """The method's parameters, lengths in the room's unit (``RoomScale``; metres where
    the scale is fixed at 1 m). Defaults: chosen by leave-one-dataset-out on the shared
    sequences (docs/groups.md, ``python -m benchmarks.groups.held_out``)."""

    stride_k: float = 0.5  # a vote's stride: this times the distance to the nearest ahead
    stride_min: float = 0.25  # ... no less (and this when nobody is ahead)
    stride_max: float = 1.0  # ... no more (GCFF: min = max, its stride)
    cone_deg: float = 70.0  # "ahead": within this of a person's heading
    mdl: float = 1.5  # the cost of one more group (GCFF's MDL), in the unit squared
    # The ring: the stride is to the point of one's heading as far from the nearest person
    # ahead as from oneself (``stride_k * d / cos(angle)``, d/2 straight across): the
    # centre of a ring both stand on, whatever its size and count. Off: the
    # stride is ``stride_k * d``, as if that person stood straight ahead.
    ring: bool = True


@dataclass(frozen=True, slots=True)
class ScaleParams:
    """How the room's unit is learnt (``RoomScale``); ``min_m == max_m`` fixes it."""

    window_s: float = 60.0  # the people of the last this long set the spacing
    # The spacing is kept within [min_m, max_m]. The default is metres (min = max = 1 m):
    # how far people stand in a conversation is proxemics, not a fraction of how crowded
    # the room is; the learnt unit (a floor of 0.5 or 0.7 m, a cap of 1.5 m) won on the
    # shared sequences but lost on rooms kept outside, and its gain on the worst held-out
    # sequence is inside its interval (docs/groups.md).
    min_m: float = 1.0
    max_m: float = 1.0
    default_m: float = 1.0  # nobody near anybody yet


class RoomScale:
    """The spacing of a room, learnt from the people in it: the median of every person's
    distance to their nearest neighbour, pooled over the frames seen in the last
    ``window_s`` (the caller's clock), within ``[min_m, max_m]``. A frame of one person
    says nothing about spacing; bounded to ``MAX_KEPT`` frames whatever the rate."""

    MAX_KEPT = 1024

    def __init__(self, params: ScaleParams) -> None:
        self.params = params
        self._seen: deque[tuple[float, FloatArray]] = deque(maxlen=self.MAX_KEPT)

    def observe(self, positions: FloatArray, now: float) -> float:
        """The room's unit (m), with the people of this frame (``(n, 2)``) seen at ``now``."""
        p = self.params
        if p.min_m == p.max_m:
            return p.min_m
        if len(positions) > 1:
            self._seen.append((now, nearest_distances(positions)))
        while self._seen and self._seen[0][0] < now - p.window_s:
            self._seen.popleft()
        if not self._seen:
            return float(np.clip(p.default_m, p.min_m, p.max_m))
        pooled = np.concatenate([d for _, d in self._seen])
        return float(np.clip(np.median(pooled), p.min_m, p.max_m))


def nearest_distances(positions: FloatArray) -> FloatArray:
    """(n,): each person's distance to their nearest neighbour (n >= 2)."""
    rel = positions[None, :, :] - positions[:, None, :]
    dist = np.hypot(rel[..., 0], rel[..., 1])
    np.fill_diagonal(dist, np.inf)
    result: FloatArray = dist.min(axis=1)
    return result


def votes(positions: FloatArray, headings: FloatArray, p: GroupParams) -> FloatArray:
    """(n, 2): each person's vote for their o-space centre, their stride ahead of them."""
    facing = np.column_stack([np.cos(headings), np.sin(headings)])
    if p.stride_min == p.stride_max:
        return positions + p.stride_min * facing
    rel = positions[None, :, :] - positions[:, None, :]  # [i, j]: j seen from i
    dist = np.hypot(rel[..., 0], rel[..., 1])
    off = np.angle(np.exp(1j * (np.arctan2(rel[..., 1], rel[..., 0]) - headings[:, None])))
    ahead = (np.abs(off) < np.radians(p.cone_deg)) & (dist > 0)
    near = np.where(ahead, dist, np.inf)
    # the nearest person ahead (where anyone is); of two as near, the one more ahead
    j = (near + TIE * np.abs(off)).argmin(axis=1)
    rows = np.arange(len(positions))
    nearest = near[rows, j]
    reach = nearest / np.cos(off[rows, j]) if p.ring else nearest
    stride = np.where(
        np.isfinite(nearest), np.clip(p.stride_k * reach, p.stride_min, p.stride_max),
        p.stride_min,
    )  # fmt: skip
    result: FloatArray = positions + stride[:, None] * facing
    return result


def _unary(
    positions: FloatArray, points: FloatArray, centres: FloatArray, mdl: float
) -> FloatArray:
    """(n, m): the squared distance of each person's vote to each centre, plus GCFF's
    visibility penalty (m²) among the people near that centre: one farther from it than
    another in about the same direction is penalised, the more the farther behind."""
    gap = points[None, :, :] - centres[:, None, :]  # (m, n, 2)
    cost: FloatArray = np.einsum("mnj,mnj->mn", gap, gap)  # (m, n)
    near = cost < mdl
    # Only among the few near each centre, padded to the most any centre has: all pairs
    # at all centres is O(n³) (16 ms for 50 people, where this takes about 1).
    rows = np.flatnonzero(near.sum(axis=1) > 1)
    if len(rows) == 0:
        return cost.T
    counts = near[rows].sum(axis=1)
    k = int(counts.max())
    members = np.argsort(~near[rows], axis=1, kind="stable")[:, :k]  # (r, k): near first
    valid = np.arange(k)[None, :] < counts[:, None]  # (r, k)
    disp = positions[members] - centres[rows][:, None, :]  # (r, k, 2)
    dist = np.maximum(np.hypot(disp[..., 0], disp[..., 1]), 1e-9)  # (r, k)
    cos = np.einsum("rkj,rlj->rkl", disp, disp) / (dist[:, :, None] * dist[:, None, :])
    ratio = dist[:, :, None] / dist[:, None, :]  # [r, k, l] > 1: k is behind l
    behind = (ratio > 1.0) & (cos > HIDDEN_COS) & valid[:, :, None] & valid[:, None, :]
    exponent = np.where(behind, np.minimum(cos * ratio, MAX_EXPONENT), 0.0)
    penalty = np.where(behind, np.power(100.0, exponent), 0.0).sum(axis=2) * CM2_TO_M2
    np.add.at(cost, (np.broadcast_to(rows[:, None], members.shape), members), penalty)
    return cost.T


def centres(points: FloatArray, labels: IntArray) -> FloatArray:
    """Each label's centre: the mean of its members' votes (least squares)."""
    count = np.bincount(labels).astype(np.float64)[:, None]
    sums = [np.bincount(labels, weights=points[:, j], minlength=len(count)) for j in (0, 1)]
    return np.column_stack(sums) / count


def detect(
    positions: FloatArray, headings: FloatArray, p: GroupParams, scale_m: float = 1.0
) -> IntArray:
    """A group label per person (0..G-1, in order of first member); a label held by one
    person is a singleton, not a group (``groups`` leaves those out). ``scale_m``: the
    room's unit (``RoomScale``), in which ``p``'s lengths are given."""
    return detect_centres(positions, headings, p, scale_m)[0]


def detect_centres(
    positions: FloatArray, headings: FloatArray, p: GroupParams, scale_m: float = 1.0
) -> tuple[IntArray, FloatArray]:
    """``detect``'s labels, and each label's o-space centre ((G, 2) in metres, by label)."""
    n = len(positions)
    if n == 0:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2))
    positions = positions / scale_m  # the room's unit: every length below is in it
    points = votes(positions, headings, p)
    labels = np.arange(n, dtype=np.int64)
    centre = points
    for _ in range(MAX_ITERATIONS):
        new = assign(_unary(positions, points, centre, p.mdl), p.mdl, place_rank(centre))
        _, new = np.unique(new, return_inverse=True)
        centre = centres(points, new)
        if np.array_equal(new, labels):
            break
        labels = new
    ordered = in_order(labels)
    return ordered, centres(points, ordered) * scale_m


def vote_centres(
    positions: FloatArray, headings: FloatArray, labels: IntArray, p: GroupParams, scale_m: float
) -> FloatArray:
    """Each label's o-space centre ((G, 2) metres, by label): the mean of its members'
    votes (a label given from elsewhere than ``detect``: the scene's memory)."""
    result: FloatArray = centres(votes(positions / scale_m, headings, p), labels) * scale_m
    return result


def in_order(labels: IntArray) -> IntArray:
    """Labels renumbered in order of their first member (stable for equal inputs)."""
    first: dict[int, int] = {}
    return np.array([first.setdefault(int(x), len(first)) for x in labels], dtype=np.int64)


#: A participant known to stand apart (the robot) is in a group only on its ring: no
#: farther from the people's o-space centre than this times the farthest of them.
RING = 1.5


def on_the_ring(
    labels: IntArray,
    positions: FloatArray,
    headings: FloatArray,
    p: GroupParams,
    scale_m: float,
    who: int,
) -> IntArray:
    """``labels`` with participant ``who`` (the robot) given a label of its own unless it
    stands on its group's ring: within ``RING`` times the farthest other member's distance
    of the o-space centre the others vote for, and no farther from it than the longest
    stride (the widest o-space the method allows: a person 2.4 m away facing the robot is
    engaging, not yet in a conversation with it). Kendon's F-formation is a ring around a
    shared space; the method's cost, lenient enough for GDet's 90-degree headings, let a
    robot that merely faces a conversation from 2 m into it (and one with a back turned
    to it within 2.2 m). People's groups are unchanged."""
    mates = np.flatnonzero((labels == labels[who]) & (np.arange(len(labels)) != who))
    if len(mates) == 0:
        return labels
    unit = positions / scale_m
    centre = votes(unit, headings, p)[mates].mean(axis=0)
    spread = np.hypot(*(unit[mates] - centre).T).max()
    if np.hypot(*(unit[who] - centre)) <= min(RING * spread, p.stride_max):
        return labels
    apart = labels.copy()
    apart[who] = labels.max() + 1
    return in_order(apart)


def members(labels: IntArray) -> list[list[int]]:
    """Each label's members, as lists of indices, in label order (``detect``'s labels
    are numbered in order of first member), singletons included."""
    out: dict[int, list[int]] = {}
    for i, label in enumerate(labels.tolist()):
        out.setdefault(label, []).append(i)
    return list(out.values())


def groups(labels: IntArray) -> list[list[int]]:
    """The groups (two or more members), as lists of indices."""
    return [m for m in members(labels) if len(m) > 1]


@dataclass(frozen=True, slots=True)
class Group:
    """A group as said: a stable id, its members, whether the robot is one, its centre, and
    where the robot should stand to join it (None: the robot is in it, it has no room, or
    it was not asked: ``scene.FrameScene`` works it out when the group is said or read)."""

    id: int
    members: frozenset[str]
    robot: bool
    centre: tuple[float, float]
    join: JoinPose | None = None


class GroupTracker:
    """Stable group ids over time, without flicker. Pure: the caller's clock.

    A grouping (the partition ``detect`` finds) is said only once it has held
    ``hold_s``: a person's heading flickering across the threshold between two readings
    does not make groups flicker (as hysteresis keeps facing calm). A group that keeps at
    least half of its members keeps its id; a new one gets the next id; a group gone is
    said dissolved. Singletons are not groups; the robot (``ROBOT``) is a member like any
    other, and a group with it says ``robot``. A member who is no longer there at all
    (lost: deleted, or silent too long) leaves every said group at once, the group keeping
    its id (dissolved when one member is left): a loss is no flicker, and a group said
    with someone already said gone is a ghost."""

    ROBOT = ""  # REP 155: the robot's id in hri_msgs/Gaze and Group is the empty string

    def __init__(self, hold_s: float) -> None:
        self.hold_s = hold_s
        self.groups: dict[int, Group] = {}
        self._next_id = 1
        self._candidate: frozenset[frozenset[str]] | None = None
        self._since = 0.0
        self._announced: frozenset[frozenset[str]] = frozenset()  # the groups' members, as said

    @property
    def pending(self) -> bool:
        """A grouping other than the one said has been seen, and is not said yet."""
        return self._candidate is not None and self._candidate != self._announced

    def update(
        self,
        found: list[tuple[frozenset[str], tuple[float, float]]],
        now: float,
        present: AbstractSet[str] | None = None,
    ) -> tuple[list[Group], list[int]]:
        """The groups ``detect`` found now (members, centre), and everyone ``present``
        (None: nobody is known gone); what changed: the groups formed or changed, and the
        ids dissolved (both empty while nothing changed)."""
        partition = frozenset(members for members, _ in found if len(members) > 1)
        if partition != self._candidate:
            self._candidate, self._since = partition, now
        if partition != self._announced and now - self._since >= self.hold_s:
            return self._adopt(found)
        if present is not None and any(not g.members <= present for g in self.groups.values()):
            return self._without_the_gone(present)
        self._recentre(found)
        return [], []

    def _without_the_gone(self, present: AbstractSet[str]) -> tuple[list[Group], list[int]]:
        """The said groups less whoever is no longer there, ids kept; a change among those
        still there waits its hold as any other."""
        changed, dissolved, now_said = [], [], {}
        for gid, group in self.groups.items():  # a new dict: callers compare it to the old
            stay = group.members & present
            if len(stay) < 2:
                dissolved.append(gid)
            elif stay == group.members:
                now_said[gid] = group
            else:
                now_said[gid] = kept = Group(gid, frozenset(stay), self.ROBOT in stay, group.centre)
                changed.append(kept)
        self.groups = now_said
        self._announced = frozenset(g.members for g in now_said.values())
        return changed, sorted(dissolved)

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
        # Most overlap first: the group that keeps most of an old group's members keeps its
        # id; of two that keep as many (an even split), the one nearer where the old group
        # stood, then by place: never by the order people or groups are listed in.
        pairs = sorted(
            (
                (-len(members & g.members), -gid, math.dist(centre, g.centre), centre, i, gid)
                for i, (members, centre) in enumerate(found)
                for gid, g in old.items()
                if len(members) > 1 and 2 * len(members & g.members) >= len(g.members)
            ),
        )
        taken: dict[int, int] = {}  # found index -> id
        for *_, i, gid in pairs:
            if i not in taken and gid not in taken.values():
                taken[i] = gid
        changed = []
        by_place = sorted(range(len(found)), key=lambda i: found[i][1])  # new ids by place
        for i in by_place:
            members, centre = found[i]
            if len(members) < 2:
                continue
            known = taken.get(i)
            if known is None:
                gid, self._next_id = self._next_id, self._next_id + 1
            else:
                gid = known
            group = Group(gid, members, self.ROBOT in members, centre)
            new[gid] = group
            if gid not in old or old[gid].members != members:
                changed.append(group)
        self.groups = new
        self._announced = frozenset(g.members for g in new.values())
        return changed, sorted(old.keys() - new.keys())
