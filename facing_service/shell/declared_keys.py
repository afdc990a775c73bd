"""The key expressions the publisher declares to zenoh: each tracked body's result key
and, on the JSON input, its pose key.

Why: zenoh caches a message's route on the *resource* of its key, and a key nobody
declared is matched against the routing tables afresh for every message, at a cost that
grows with the resources under the same prefix. A client-mode tracker's declared
publishers put one resource per body under ``NS/bodies/``: each undeclared result then
cost ~35 us of matching; our own declared results did the same to every undeclared pose
a ``Session.put`` tracker sent. With both keys declared here, both directions hit the
cache whatever the tracker and the consumers do (``python -m benchmarks``, the grid: the relay
that declares its keys is the cheapest relay in 11 of 12 cells, the twelfth a tie).

Declaring costs once per body (5 us with 100 declared, ~130 us with 4 000: zenoh matches
the new resource against the others), so a pair is kept while its body is tracked,
undeclared when the body is lost, and the oldest pair goes past ``CAPACITY``: memory and
routing tables stay bounded whatever ids a peer invents.
"""

from __future__ import annotations

import zenoh

from ..contract import keys


class DeclaredKeys:
    """Used by the publisher thread alone. ``results`` maps a result key to its declared
    key expression, read on the hot path; ``declare`` adds a body's pair."""

    CAPACITY = 4096

    def __init__(self, session: zenoh.Session, namespace: str, inputs: bool) -> None:
        self._session = session
        self._namespace = namespace
        self._inputs = inputs  # also declare the pose key: poses come on our JSON keys
        self.results: dict[str, zenoh.KeyExpr] = {}
        self._poses: dict[str, zenoh.KeyExpr] = {}  # by result key

    def declare(self, key: str) -> zenoh.KeyExpr:
        """The declared key expression of the result key ``key``, declared (with its
        pose key) now; the oldest pair is undeclared past ``CAPACITY``."""
        if len(self.results) >= self.CAPACITY:
            self.forget(next(iter(self.results)))
        declared = self.results[key] = self._session.declare_keyexpr(key)
        if self._inputs:
            body = keys.body_of(key)
            pose = keys.pose_key(self._namespace, body.body_id, body.frame_id)
            self._poses[key] = self._session.declare_keyexpr(pose)
        return declared

    def forget(self, key: str) -> None:
        """The body of the result key ``key`` is lost: undeclare its pair, if declared."""
        for declared in (self.results.pop(key, None), self._poses.pop(key, None)):
            if declared is not None:
                self._session.undeclare(declared)

    def close(self) -> None:
        for key in list(self.results):
            self.forget(key)
