"""The key expressions the JSON output declares to zenoh: every per-body key it puts on
(each tracked body's result and engagement keys; the JSON input declares its pose keys
itself, ``inputs.PoseKeys``).

Why: zenoh caches a message's route on the *resource* of its key, and a key nobody
declared is matched against the routing tables afresh for every message, one test per
resource under the same prefix (``NS/bodies/``). A client-mode tracker's declared
publishers put one resource per body there: each undeclared result then cost ~35 us of
matching with 100 bodies; our own declared keys do the same to any undeclared key beside
them (a string put on an engagement key: 21 us with 100 bodies declared, 258 us with
1 000, 1.4 ms with 4 000). With every per-body key we send, and the poses we receive,
declared (by the input), both directions hit the cache whatever the tracker and the consumers do
(``python -m benchmarks``, the grid: the relay that declares its keys is the cheapest
relay in 11 of 12 cells, the twelfth a tie).

Declaring costs once per key (5 us with 100 declared, ~130 us with 4 000: zenoh matches
the new resource against the others); a key is undeclared with its DELETE (the body is
lost). At most ``capacity`` keys of each kind, the tracker's own bound on bodies, so every
tracked body has its keys; past it (never, while the tracker holds its bound) a key goes
out as its string, uncached. Nothing is evicted to make room: a crowd larger than the
room, each body in turn, would evict on every result (measured with eviction, 5 000
bodies and room for 4 096: 1.4 ms a result against 2.8 us). Memory and routing tables stay
bounded whatever ids a peer invents.
"""

from __future__ import annotations

import zenoh


class DeclaredKeys:
    """Used by one thread alone. ``exprs`` maps a per-body key to its declared key
    expression, read on the hot path; ``declare`` adds one. ``capacity``: the most keys."""

    def __init__(self, session: zenoh.Session, capacity: int):
        self._session = session
        self._capacity = capacity
        self.exprs: dict[str, zenoh.KeyExpr] = {}

    def declare(self, key: str) -> zenoh.KeyExpr | str:
        """What to put the per-body key ``key`` on: its key expression, declared now, or
        ``key`` itself when there is no room."""
        if len(self.exprs) >= self._capacity:
            return key
        declared = self.exprs[key] = self._session.declare_keyexpr(key)
        return declared

    def forget(self, key: str) -> None:
        """``key`` was deleted (its body is lost): undeclare it."""
        if (declared := self.exprs.pop(key, None)) is not None:
            self._session.undeclare(declared)

    def close(self) -> None:
        """Undeclare every key (the owner is closing)."""
        for key in list(self.exprs):
            self.forget(key)
