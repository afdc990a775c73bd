"""Publications waiting between the worker (which decides) and the publisher (which sends).

Sending can block: a consumer that stops reading fills zenoh's queue, and a BLOCK put then
waits (up to zenoh's ``wait_before_close``, 5 s by default, before zenoh drops that link).
Keeping that wait off the worker means one stuck consumer never stalls ingestion, state or
queries.

Everything is sent, in order. While the publisher makes progress, however slowly (it
sends with BLOCK, so a slow consumer slows it down), a worker that has ``limit``
publications pending waits for room: the slowness reaches the inputs as back-pressure
and nothing is lost. (Conflating a merely slow publisher lost 5 % of a 100 000-pose burst
once the worker got faster than the publisher.) Only when the publisher has made no
progress for ``stall_s`` (a consumer stopped reading and a put is blocked) does the worker
stop waiting, and per-body results *conflate*: a newer result for a key replaces the
pending one, which it supersedes; this is counted, never silent, and keeps memory bounded
by ``limit`` plus the number of bodies. Deletes, aggregates and engagement changes never
conflate and are never dropped.
"""

from __future__ import annotations

import itertools
import threading
import time
from collections import OrderedDict
from collections.abc import Iterable
from enum import Enum
from typing import NamedTuple

DEFAULT_LIMIT = 10_000
#: No progress from the publisher for this long means a put is blocked on a stuck
#: consumer: the worker stops waiting for room and conflates (one such wait at most).
DEFAULT_STALL_S = 0.5


class Kind(str, Enum):
    """What a publication says: the sender that sends it (the robot's for ROS, the JSON
    output's for the others) and the counter that counts it. Whether it is a PUT or a
    DELETE is the payload's (None: DELETE), and whether it may be superseded is
    ``Publication.supersedable``'s: neither is a kind."""

    RESULT = "result"  # a body's facing result
    FRAME = "frame"  # a frame's aggregate
    ENGAGEMENT = "engagement"  # a body's engagement level
    EVENT = "event"  # a change of engagement level
    ROS = "ros"  # a message on the robot's own topics (--output ros2)
    SCENE = "scene"  # a frame's groups, a group, who faces whom


class Publication(NamedTuple):
    """One thing to send. A named tuple: one is made per result, and a tuple is the
    cheapest immutable record Python builds (a frozen dataclass cost 8 % of the worker)."""

    key: str  # a zenoh key; for Kind.ROS, the ROS topic
    #: None: a DELETE (a body lost: its result and engagement keys; a group dissolved;
    #: for Kind.ROS: undeclare the topic)
    payload: bytes | None
    kind: Kind
    typename: str | None = None  # Kind.ROS: the message type

    @property
    def supersedable(self) -> bool:
        """Only a body's result may be replaced by its newer one, past the limit: every
        other publication, and every DELETE, is a state change sent as it is."""
        return self.kind is Kind.RESULT and self.payload is not None


class Outbox:
    def __init__(self, limit: int = DEFAULT_LIMIT, stall_s: float = DEFAULT_STALL_S) -> None:
        self.limit = limit
        self.stall_s = stall_s
        self._progress = time.monotonic()  # when the publisher last took or sent
        self._cond = threading.Condition()
        self._pending: OrderedDict[int, Publication] = OrderedDict()
        self._latest_result: dict[str, int] = {}  # key -> slot of its newest pending result
        self._slots = itertools.count()
        self._closed = False
        self._in_flight = 0  # taken by the publisher, not yet reported sent
        self.superseded = 0  # results replaced before they could be sent

    def add(self, publications: Iterable[Publication]) -> None:
        """Publications in the order they must be sent; one lock and one wake-up for all.

        With ``limit`` pending, waits for room while the publisher makes progress. Once it
        has stalled, a per-body result past ``limit`` replaces the pending result for its
        key (counted in ``superseded``); every other kind is kept, in order.
        """
        with self._cond:
            pending, latest = self._pending, self._latest_result
            if not pending and not self._in_flight:  # the publisher was idle, not stalled
                self._progress = time.monotonic()
            while len(pending) >= self.limit and not self._closed and not self._stalled():
                self._cond.wait(self.stall_s / 5)
            conflate = self._stalled()
            for publication in publications:
                slot = next(self._slots)
                if publication.supersedable:
                    if conflate and len(pending) >= self.limit:
                        old = latest.get(publication.key)
                        if old is not None and pending.pop(old, None) is not None:
                            self.superseded += 1
                    latest[publication.key] = slot
                pending[slot] = publication
            self._cond.notify()

    def take(self, timeout: float | None = None) -> list[Publication]:
        """Everything pending, oldest first; waits up to ``timeout`` for something.

        What is taken stays counted in ``len()`` until ``sent()`` reports it, so the depth
        never reads 0 while publications are on their way. Returns an empty list on
        time-out or once closed and empty.
        """
        with self._cond:
            if not self._pending and not self._closed:
                self._cond.wait(timeout)
            taken = list(self._pending.values())
            self._pending.clear()
            self._latest_result.clear()
            self._in_flight += len(taken)
            if taken:
                self._progress = time.monotonic()
                self._cond.notify_all()  # room for a worker waiting in add()
            return taken

    def sent(self, n: int = 1) -> None:
        """The publisher is done with ``n`` taken publications. No lock: only the
        publisher's thread changes ``_in_flight`` (here and in ``take``)."""
        self._in_flight -= n
        self._progress = time.monotonic()

    def _stalled(self) -> bool:
        """The publisher holds publications it has not moved for ``stall_s``."""
        return bool(self._pending) and time.monotonic() - self._progress > self.stall_s

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self._cond.notify_all()

    @property
    def closed(self) -> bool:
        return self._closed

    def __len__(self) -> int:
        """Publications not yet sent: pending, plus taken and still in flight."""
        with self._cond:
            return len(self._pending) + self._in_flight
