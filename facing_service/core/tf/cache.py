"""One frame's history, as tf2's ``cache.cpp`` keeps it: a static cache (valid at every time)
or a time cache (``cache_time`` of history pruned relative to the newest stamp, bounded
in entries; the two stamps around a time found and interpolated).
"""

from __future__ import annotations

from bisect import bisect_left
from dataclasses import dataclass

from .errors import ExtrapolationError
from .geometry import RigidTransform, lerp, slerp

S_NS = 1_000_000_000
DEFAULT_CACHE_TIME_NS = 10 * S_NS


#: Most transforms one dynamic frame keeps (10 s at 1 kHz): see ``TimeCache``.
MAX_CACHE_ENTRIES = 10_000


@dataclass(frozen=True, slots=True)
class Stored:
    stamp: int
    parent: str
    transform: RigidTransform


def _seconds(ns: int) -> str:
    return f"{ns // 1_000_000_000}.{ns % 1_000_000_000:09d}"


class StaticCache:
    """One transform, valid at every time."""

    is_static = True

    def __init__(self) -> None:
        self.item: Stored | None = None

    def insert(self, item: Stored) -> str | None:
        self.item = item
        return None

    def get(self, time: int) -> Stored:
        assert self.item is not None
        return Stored(time, self.item.parent, self.item.transform)

    def latest(self) -> tuple[int, str | None]:
        return (0, self.item.parent) if self.item else (0, None)


class TimeCache:
    """History of one dynamic frame, newest first, with the stamps negated beside it
    (ascending, for ``bisect``): an insert or a lookup costs O(log n) comparisons however
    the stamps arrive (a linear scan let 4 MB of out-of-order /tf stall the worker for a
    minute). At most ``MAX_CACHE_ENTRIES`` are kept: tf2 bounds a frame's history by time
    only, so transforms 1 ns apart would grow it without bound; past the cap the oldest go
    first, as pruning by time would take them."""

    is_static = False

    def __init__(self, cache_time: int) -> None:
        self.cache_time = cache_time
        self.items: list[Stored] = []  # newest first
        self._keys: list[int] = []  # -stamp of each item, ascending

    def insert(self, item: Stored) -> str | None:
        items, keys = self.items, self._keys
        if items and items[0].stamp > item.stamp + self.cache_time:
            return "old_data"
        i = bisect_left(keys, -item.stamp)
        if i < len(keys) and keys[i] == -item.stamp:
            return "repeated_data"
        items.insert(i, item)
        keys.insert(i, -item.stamp)
        latest = items[0].stamp
        while items and (
            items[-1].stamp + self.cache_time < latest or len(items) > MAX_CACHE_ENTRIES
        ):
            items.pop()
            keys.pop()
        return None

    def _closest(self, time: int) -> tuple[Stored, Stored | None]:
        """tf2's ``findClosest``: one or two items, or ExtrapolationError."""
        items = self.items
        if not items:
            raise ExtrapolationError("no data")  # unreachable: caches exist once filled
        if time == 0:
            return items[0], None
        if len(items) == 1:
            if items[0].stamp == time:
                return items[0], None
            raise ExtrapolationError(
                f"Lookup would require extrapolation at time {_seconds(time)}, but only time "
                f"{_seconds(items[0].stamp)} is in the buffer"
            )
        latest, earliest = items[0].stamp, items[-1].stamp
        if time == latest:
            return items[0], None
        if time == earliest:
            return items[-1], None
        if time > latest:
            raise ExtrapolationError(
                f"Lookup would require extrapolation into the future.  Requested time "
                f"{_seconds(time)} but the latest data is at time {_seconds(latest)}"
            )
        if time < earliest:
            raise ExtrapolationError(
                f"Lookup would require extrapolation into the past.  Requested time "
                f"{_seconds(time)} but the earliest data is at time {_seconds(earliest)}"
            )
        i = bisect_left(self._keys, -time)  # the first item at or before ``time``
        return items[i], items[i - 1]  # older, newer

    def get(self, time: int) -> Stored:
        one, two = self._closest(time)
        if two is None or one.parent != two.parent:
            return one
        if two.stamp == one.stamp:
            return two
        ratio = (time - one.stamp) / (two.stamp - one.stamp)
        a, b = one.transform, two.transform
        return Stored(
            time,
            one.parent,
            RigidTransform(
                lerp(a.translation, b.translation, ratio),
                slerp(a.rotation, b.rotation, ratio),
            ),
        )

    def latest(self) -> tuple[int, str | None]:
        return (self.items[0].stamp, self.items[0].parent) if self.items else (0, None)

    def stamps(self, after: int, upto: int) -> list[int]:
        """The stamps held in ``(after, upto]``, oldest first."""
        keys = self._keys
        return [-k for k in reversed(keys[bisect_left(keys, -upto) : bisect_left(keys, -after)])]
