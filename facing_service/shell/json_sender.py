"""How our JSON keys go out (docs/contract.md), on the publisher thread: per-body results
and engagement on key expressions declared per body (``declared_keys``), the rest on
their strings, every one with BLOCK (a slow consumer slows the publisher, never loses a
state change).

It also tells the worker whether anyone listens to the results at all (``Heard``): a
publisher declared on the whole result space (never put on) has zenoh's matching status,
true while any subscriber anywhere matches a result key. While nobody does, the JSON
output neither formats nor sends results, the bulk of what the service says (one per
pose); queries still answer from state. When a subscriber appears, the worker is woken
and says every tracked body's current result at once (but those already sent since,
``outputs.JsonOutput.tick``): a consumer that subscribes and then sees a single pose
(zenoh tells the service of it a moment later) still gets it.
Only results are skipped: a skipped engagement change, event, aggregate or DELETE would
stay wrong until the next change.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

import zenoh

from ..contract import keys
from .declared_keys import DeclaredKeys
from .outbox import Kind, Publication

JSON = zenoh.Encoding.APPLICATION_JSON
BLOCK = zenoh.CongestionControl.BLOCK
#: The kinds put on a key of their body's, declared (the others on their strings).
_PER_BODY = (Kind.RESULT, Kind.ENGAGEMENT)


class Heard:
    """Whether a subscriber matches the result keys, and whether one appeared that the
    worker has yet to say the current results to: written by zenoh's matching listener,
    read by the worker, both under one small lock (two plain attributes written
    by two threads in an order that mattered lost a join between the worker's check and
    its clear). ``results`` is true until zenoh says otherwise, so nothing is skipped
    before the listener is in place. Each appearance has a number of its own, so what the
    worker collected for one is never taken for another's. ``wake`` wakes the worker (the
    service gives it, once the worker's intake exists)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._results = True
        self._appearances = 0
        self._due: int | None = None  # the appearance the current results are due to
        self.wake: Callable[[], None] | None = None

    @property
    def results(self) -> bool:
        return self._results  # one attribute read: atomic

    def matching(self, matching: bool) -> None:
        """What zenoh says now; a subscriber that appears wakes the worker to say the
        current results. One that vanishes before the worker said them is owed nothing."""
        with self._lock:
            appeared = matching and not self._results
            if appeared:
                self._appearances += 1
                self._due = self._appearances
            elif not matching:
                self._due = None
            self._results = matching
        if appeared and self.wake is not None:
            self.wake()

    def now(self) -> tuple[bool, int | None]:
        """Whether results are heard, and the appearance they are due to (None: none)."""
        with self._lock:
            return self._results, self._due

    def take_due(self) -> int | None:
        """The appearance the current results are due to, now being said (None: none)."""
        with self._lock:
            due, self._due = self._due, None
            return due


class JsonSender:
    """Sends the JSON output's publications. ``capacity``: the most bodies tracked (each
    has a result and an engagement key declared)."""

    kinds = frozenset({Kind.RESULT, Kind.FRAME, Kind.ENGAGEMENT, Kind.EVENT, Kind.SCENE})

    def __init__(self, session: zenoh.Session, namespace: str, capacity: int, heard: Heard):
        self._session = session
        self._keys = DeclaredKeys(session, 2 * capacity)
        self._heard = heard  # before the listener: it may call back at once, on its thread
        space = keys.facing_key(namespace, body_id=keys.ALL_FRAMES, frame_id=keys.ALL_FRAMES)
        self._watch = session.declare_publisher(space)
        self._listener = self._watch.declare_matching_listener(self._on_matching)
        # zenoh 1.10's stub says bool; the property is a MatchingStatus, as the listener's
        status: Any = self._watch.matching_status
        heard.matching(bool(status.matching))

    def _on_matching(self, status: zenoh.MatchingStatus) -> None:
        self._heard.matching(status.matching)

    def send(self, p: Publication) -> None:
        """One publication, on its declared key when it has one."""
        key: zenoh.KeyExpr | str | None = self._keys.exprs.get(p.key)
        if p.payload is None:  # a DELETE: the body is lost (or a group dissolved)
            self._session.delete(p.key if key is None else key, congestion_control=BLOCK)
            self._keys.forget(p.key)
            return
        if key is None:
            key = self._keys.declare(p.key) if p.kind in _PER_BODY else p.key
        self._session.put(key, p.payload, encoding=JSON, congestion_control=BLOCK)

    def close(self) -> None:
        self._listener.undeclare()
        self._watch.undeclare()
        self._keys.close()
