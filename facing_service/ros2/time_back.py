"""When a robot's clock went back (a recording replayed again, a clock reset), told from
the /tf stamps alone: ROS's TF listener clears its buffer when its clock jumps back, and
the service has no clock of the robot's but its stamps.

Time went back after ``TIME_BACK_MESSAGES`` /tf messages in a row *from one publisher*
(rmw_zenoh's GID, when the caller knows it), spanning at least ``TIME_BACK_SPAN_S`` of
receive time, whose every transform is more than ``TIME_BACK_NS`` older than its frame's
newest. In a row: a stale or forged message between fresh ones tells nothing, and a burst
of forged ones cannot span the time while the robot streams. At most one clear in
``CLEAR_MIN_INTERVAL_S`` (the others are counted as refused). Pure.
"""

from __future__ import annotations

from collections.abc import Iterable

from ..contract.stamps import NS_PER_S

#: How far back a transform's stamp must be, for how many /tf messages in a row from one
#: publisher, over how much receive time, for time to have gone back (a stream at 30 Hz
#: says so within a third of a second).
TIME_BACK_NS = NS_PER_S // 2
TIME_BACK_MESSAGES = 3
TIME_BACK_SPAN_S = 0.25
#: At most one TF buffer clear in this long (a replay looping every few seconds is still
#: followed; a flood of forged rewinds is not).
CLEAR_MIN_INTERVAL_S = 2.0


class TimeBack:
    """The evidence that time went back, message by message; ``clears`` and
    ``clears_refused`` count what it concluded."""

    def __init__(self) -> None:
        # /tf messages whose every transform went back in time: (publisher, count, since)
        self._run: tuple[bytes | None, int, float | None] = (None, 0, None)
        self._last_clear: float | None = None  # receive time of the last clear
        self.clears = 0
        self.clears_refused = 0

    @property
    def under_way(self) -> bool:
        """Messages that went back were seen, and time has not been said to go back yet."""
        return self._run[1] > 0

    def observe(
        self,
        stamps: Iterable[tuple[int | None, int | None]],
        publisher: bytes | None,
        received_s: float | None,
    ) -> int:
        """One /tf message from ``publisher``, received at ``received_s`` (None: judge by
        messages alone), as each transform's ``(stamp, its frame's newest stamp)``: how
        far back time went, once it has (0: it has not)."""
        back = []
        for stamp, newest in stamps:
            if stamp is None:
                continue  # no time at all: refused, and no sign of time going back
            if newest is None or stamp >= newest - TIME_BACK_NS:
                self._run = (None, 0, None)  # a fresh (or first) transform: time goes on
                return 0
            back.append(newest - stamp)
        if not back:
            return 0
        who, count, since = self._run
        if count == 0 or who != publisher:
            who, count, since = publisher, 0, received_s
        self._run = (who, count + 1, since)
        if count + 1 < TIME_BACK_MESSAGES:
            return 0
        if received_s is not None and since is not None:
            if received_s - since < TIME_BACK_SPAN_S:
                return 0  # a burst: not yet a clock that went back
            if (
                self._last_clear is not None
                and received_s - self._last_clear < CLEAR_MIN_INTERVAL_S
            ):
                self.clears_refused += 1
                self._run = (None, 0, None)
                return 0
            self._last_clear = received_s
        self._run = (None, 0, None)
        self.clears += 1
        return max(back)
