"""The place a member who just left a group stood in: the room the group leaves for a
newcomer, kept while it stays clear and by the group.

A robot watches a stream: when a group's member walks away, the group keeps its id and
the place they stood in is, for a while, the gap a person joining would take. Worked
out from the remaining people alone, the place may be elsewhere (a pair's two sides look
alike), or the group itself read otherwise; the place they left is what the group said
last. Pure: the caller's groups and positions; no clock: a place is kept exactly as long
as nobody takes it (nobody else as close to it as the members stand to each other, no
member stepping into it) and the group stays where it was.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from .groups import Group

FloatArray = NDArray[np.float64]
Seats = dict[str, tuple[float, float]]


class Vacancies:
    """Where each said group's members stood when last seen together, and the place one
    of them left."""

    def __init__(self) -> None:
        self._seats: dict[int, Seats] = {}  # group id -> member -> where they stood
        #: group id -> the place left, and where the members who stayed stood then
        self._left: dict[int, tuple[tuple[float, float], tuple[float, float]]] = {}

    def __contains__(self, gid: object) -> bool:
        """Whether group ``gid`` has a place left (still to be checked by ``place``)."""
        return gid in self._left

    def seen(
        self,
        groups: Mapping[int, Group],
        before: Mapping[int, Group],
        found: set[frozenset[str]],
        where: Mapping[str, tuple[float, float]],
    ) -> None:
        """The groups as said now (and as said ``before`` this update), the memberships the
        computation ``found``, and where everyone stands (``where``): a group that kept its
        id but lost members (others may have joined it) leaves the place the member stood
        in; several leaving in one update leave the one nearest the robot (the frame's
        origin: the least way to go), whatever they are called (the largest id
        was taken for "the last")."""
        for gid, group in groups.items():
            old = before.get(gid)
            if old is not None and old.members - group.members and gid in self._seats:
                seats = self._seats[gid]
                gone = [seats[m] for m in old.members - group.members if m in seats]
                stayed = [where[m] for m in group.members if m in where]
                if gone and stayed:
                    x, y = np.mean(stayed, axis=0).tolist()
                    self._left[gid] = (min(gone, key=lambda s: (math.hypot(*s), s)), (x, y))
            if group.members in found:  # seen together now: where they stand
                self._seats[gid] = {m: where[m] for m in group.members if m in where}
        for gid in set(self._seats) - set(groups):
            del self._seats[gid]
            self._left.pop(gid, None)

    def place(
        self, gid: int, members: FloatArray, others: FloatArray, clear_m: float, body_m: float
    ) -> tuple[float, float] | None:
        """The place left in group ``gid`` if nobody else (``others``, (k, 2)) stands within
        ``clear_m`` of it, no member within ``body_m`` (they stood beside it: only one who
        steps into it takes it), and the ``members`` ((n, 2)) stand where they stood when
        it was left (their centroid within ``clear_m``); else None, and it is forgotten: a
        place taken, or a group gone on, leaves no gap."""
        kept = self._left.get(gid)
        if kept is None:
            return None
        left, then = kept
        centroid = members.mean(axis=0)
        if (
            _nearest(others, left) >= clear_m
            and _nearest(members, left) >= body_m
            and math.hypot(centroid[0] - then[0], centroid[1] - then[1]) <= clear_m
        ):
            return left
        del self._left[gid]
        return None


def _nearest(points: FloatArray, place: tuple[float, float]) -> float:
    return float(np.hypot(*(points - np.array(place)).T).min()) if len(points) else math.inf
