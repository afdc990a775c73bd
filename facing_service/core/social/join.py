"""Where the robot should stand to join a group: a place on the group's ring, clear of
everyone, facing into its o-space. Pure numpy, metres and radians in one base
frame.

Kendon's F-formation is a ring of people around a shared space (the o-space) that they
all face; a newcomer joins by taking a place on that ring where there is room. So:

1. **The o-space centre** is estimated from both what the members' places and what their
   headings say: halfway between their centroid and the mean of their votes (each member's
   place moved ``stride_k`` times the members' mean spacing along their heading). The
   centroid alone is wrong for an open arc (two people side by side facing a third place);
   the votes alone are wrong for coarse headings (annotated to 90°).
2. **The ring** is the members' mean distance from that centre (never under
   ``min_radius_m``).
3. **Room**: a place on the ring is clear when nobody (member or not) stands closer to it
   than the members stand to each other (``clearance_k`` times their median nearest
   spacing, at least ``min_clearance_m``): the robot is no closer to anyone than a person
   of the group would stand to another.
4. **Which place**: the clear places form free arcs; each arc offers its middle (the
   middle of the gap between the people on either side of it). The group says which: the
   room it leaves is its widest free arc, as a person joining takes it wherever they came
   from (the arc nearest the robot won, so the place depended on where the
   robot happened to be, by up to 0.5 m in a sequence's median). Where the robot stands only
   breaks near-ties: among arcs at least ``tie`` of the widest, the nearest. None is
   clear: the group has no room, and no place is said.

The heading is toward the o-space centre: facing into the group. ``offered`` is what the
group says (every arc's place, the robot aside), ``chosen`` where a robot goes: a caller
that asks for many robots' places (the benchmark) works the first out once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class JoinParams:
    """Chosen held out by dataset on the shared sequences (``python -m benchmarks.groups.join``)."""

    stride_k: float = 0.5  # a member's vote: this times the members' mean spacing ahead
    clearance_k: float = 0.6  # nobody closer to the place than this times their spacing
    min_clearance_m: float = 0.3  # ... and never closer than this
    steps: int = 72  # places looked at around the ring (every 5°)
    widen: tuple[float, ...] = (1.0, 1.15)  # no room on the ring: a step back
    tie: float = 1.0  # arcs at least this share of the widest: a near-tie, the robot's nearest
    # The ring is never smaller than this (m): people who stand close (two of a group a
    # hand apart) leave no place on a ring that small; a newcomer stands at a conversation's
    # distance from its centre.
    min_radius_m: float = 0.4


@dataclass(frozen=True, slots=True)
class JoinPose:
    """Where to stand (metres) and which way to face (radians, from +x), in the base frame."""

    x: float
    y: float
    yaw: float


def o_space(positions: FloatArray, headings: FloatArray, p: JoinParams) -> tuple[FloatArray, float]:
    """The o-space centre ((2,)) and the ring's radius of ``n >= 2`` members."""
    rel = positions[:, None, :] - positions[None, :, :]
    distance = np.hypot(rel[..., 0], rel[..., 1])
    n = len(positions)
    spacing = float(distance.sum() / (n * (n - 1)))
    facing = np.column_stack([np.cos(headings), np.sin(headings)])
    votes = positions + p.stride_k * spacing * facing
    centre = 0.5 * (positions.mean(axis=0) + votes.mean(axis=0))
    radius = max(float(np.hypot(*(positions - centre).T).mean()), p.min_radius_m)
    return centre, radius


def clearance(positions: FloatArray, p: JoinParams) -> float:
    """How far from everyone a place must be: as far as the members stand from each other."""
    rel = positions[:, None, :] - positions[None, :, :]
    distance = np.hypot(rel[..., 0], rel[..., 1])
    np.fill_diagonal(distance, np.inf)
    nearest = np.sort(distance.min(axis=1))  # their median (np.median costs 20x on a few)
    n = len(nearest)
    return max(
        p.min_clearance_m, p.clearance_k * float(nearest[(n - 1) // 2] + nearest[n // 2]) / 2
    )


@dataclass(frozen=True, slots=True)
class Offered:
    """The places a group offers a newcomer: the middle of each free arc of its ring, with
    the arc's width (places of ``2π / steps``), and the o-space centre they face."""

    centre: tuple[float, float]
    places: tuple[tuple[float, float, int], ...]  # (x, y, width)


def offered(
    members: FloatArray, headings: FloatArray, others: FloatArray, p: JoinParams
) -> Offered | None:
    """Where a newcomer could stand in the group of ``members`` ((n, 2), n >= 2, with
    their ``headings``), clear of them and of ``others`` ((m, 2): everyone else in the
    frame): on the ring, else a step back; None when neither has room."""
    centre, ring = o_space(members, headings, p)
    clear_m = clearance(members, p)
    around = _around(p.steps)
    everyone = np.vstack([members, others]) if len(others) else members
    for radius in (ring * f for f in p.widen):  # the ring first, then a step back
        gap = (centre + radius * around)[:, None, :] - everyone[None, :, :]
        free = np.hypot(gap[..., 0], gap[..., 1]).min(axis=1) >= clear_m
        arcs = _arcs(free)
        if arcs:
            cx, cy = float(centre[0]), float(centre[1])
            return Offered((cx, cy), tuple(
                (cx + radius * math.cos(middle), cy + radius * math.sin(middle), width)
                for middle, width in arcs
            ))  # fmt: skip
    return None


def chosen(offer: Offered, robot: tuple[float, float], p: JoinParams) -> JoinPose:
    """The place the group leaves most room at; among near-ties (``tie`` of the widest),
    the nearest to ``robot``; facing the o-space centre."""
    widest = max(width for _, _, width in offer.places)
    x, y, _ = min(
        (place for place in offer.places if place[2] >= p.tie * widest),
        key=lambda place: math.hypot(place[0] - robot[0], place[1] - robot[1]),
    )
    return JoinPose(x, y, math.atan2(offer.centre[1] - y, offer.centre[0] - x))


def join_pose(
    members: FloatArray,
    headings: FloatArray,
    others: FloatArray,
    robot: tuple[float, float],
    p: JoinParams,
) -> JoinPose | None:
    """Where the robot should stand to join the group of ``members`` (see ``offered``),
    seen from ``robot``; None when the group has no room."""
    offer = offered(members, headings, others, p)
    return None if offer is None else chosen(offer, robot, p)


@cache
def _around(steps: int) -> FloatArray:
    """Unit vectors to the ``steps`` places around a ring, every ``2π / steps``."""
    angles = np.arange(steps) * (2 * math.pi / steps)
    return np.column_stack([np.cos(angles), np.sin(angles)])


def _arcs(free: NDArray[np.bool_]) -> list[tuple[float, int]]:
    """Every run of free places around the ring (``free[k]``: the place at ``k`` steps of
    ``2π / len(free)``), a run across the start counted once: its middle angle and how
    many places it holds."""
    steps = len(free)
    if free.all():
        return [(0.0, steps)]
    start = int(np.argmin(free))  # a taken place: runs are read from just after it
    arcs: list[tuple[float, int]] = []
    run: list[int] = []
    for k in range(1, steps + 1):
        i = (start + k) % steps
        if free[i]:
            run.append(start + k)
        elif run:
            arcs.append(((run[0] + run[-1]) / 2 * (2 * math.pi / steps), len(run)))
            run = []
    return arcs
