"""Real zenoh networks on loopback for tests: configs, readiness, recording subscribers."""

from __future__ import annotations

import functools
import json
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import zenoh

from facing_service.testing import endpoint, free_port, loopback_config, wait_until

LOOPBACK_CFG = ["scouting/delay:0"]

__all__ = ["endpoint", "free_port", "loopback_config"]  # re-exported for the tests


@dataclass(frozen=True, eq=False)
class Received:
    key: str
    kind: str  # "put" or "delete"
    payload: bytes

    @functools.cached_property
    def value(self) -> Any:
        """The decoded JSON of a put (decoded on first use: floods stay cheap to record)."""
        return json.loads(self.payload) if self.kind == "put" else None


class Recorder:
    """Everything a subscriber receives, with waiting helpers. Close it (or its session)."""

    def __init__(self, session: zenoh.Session, key_expr: str) -> None:
        self._cond = threading.Condition()
        self.items: list[Received] = []
        self._sub = session.declare_subscriber(key_expr, self._on_sample)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        put = sample.kind == zenoh.SampleKind.PUT
        item = Received(str(sample.key_expr), "put" if put else "delete", sample.payload.to_bytes())
        with self._cond:
            self.items.append(item)
            self._cond.notify_all()

    def wait_for(
        self, predicate: Callable[[Received], bool], count: int = 1, timeout: float = 5.0
    ) -> list[Received]:
        """The first ``count`` received items matching ``predicate``; AssertionError on time-out."""
        deadline = time.monotonic() + timeout
        with self._cond:
            while True:
                matching = [i for i in self.items if predicate(i)]
                if len(matching) >= count:
                    return matching[:count]
                left = deadline - time.monotonic()
                if left <= 0:
                    raise AssertionError(
                        f"waited {timeout} s for {count} matching samples, got {len(matching)}; "
                        f"all received: {self.items[-20:]}"
                    )
                self._cond.wait(left)

    def on(self, key: str) -> list[Received]:
        with self._cond:
            return [i for i in self.items if i.key == key]

    def close(self) -> None:
        self._sub.undeclare()


def get(session: zenoh.Session, selector: str, timeout: float = 5.0) -> list[tuple[str, Any]]:
    """All replies to a query: ``(key, json)`` for data, ``("error", json)`` for errors."""
    replies = []
    for reply in session.get(selector, timeout=timeout):
        if reply.ok is not None:
            replies.append((str(reply.ok.key_expr), json.loads(reply.ok.payload.to_bytes())))
        else:
            replies.append(("error", json.loads(reply.err.payload.to_bytes())))
    return replies


def results(replies: list[tuple[str, Any]]) -> list[tuple[str, Any]]:
    """The data replies of ``get``'s: a query on a known frame with nobody (yet) gets an
    error reply that says so, not silence."""
    return [reply for reply in replies if reply[0] != "error"]


def wait_until_answered(session: zenoh.Session, selector: str, timeout: float = 10.0) -> None:
    """Block until a queryable answers ``selector``: the service is connected and declared
    (its subscriber was declared before its queryables, on the same ordered link)."""
    wait_until(
        lambda: bool(get(session, selector, timeout=0.5)), timeout, f"an answer on {selector}"
    )


def send(session: zenoh.Session, key: str, payload: bytes) -> None:
    """Publish a pose as a tracker should: BLOCK, since zenoh's default (DROP) silently
    loses samples on the sending side under a burst."""
    session.put(
        key,
        payload,
        encoding=zenoh.Encoding.APPLICATION_JSON,
        congestion_control=zenoh.CongestionControl.BLOCK,
    )


def send_delete(session: zenoh.Session, key: str) -> None:
    session.delete(key, congestion_control=zenoh.CongestionControl.BLOCK)
