"""The publisher thread: sends what the outbox holds, in order, every output with BLOCK.

It is the only thread that waits on the network. A slow consumer slows it down; one that
stops reading blocks it (up to zenoh's ``wait_before_close``), while the worker keeps
ingesting, deciding and answering (see ``outbox``).

Per-body results go out through ``Session.put`` by default, or through a publisher
declared per body (``--result-publishers declared``). Which is cheaper depends on how the
trackers connect (``python -m benchmarks.grid``): a put on an undeclared key has zenoh
match its routes each time, ~35 us a result where a client-mode tracker declared its
publishers; declared output resources make zenoh's receive threads match each undeclared
incoming pose against them, +5 % of a core under a peer-mode ``Session.put`` tracker.
"""

from __future__ import annotations

import logging
import threading
from collections import OrderedDict
from collections.abc import Callable

import zenoh

from ..ros2.output import RosMessage, RosPublishers
from .ledger import Ledger
from .outbox import Kind, Outbox, Publication

log = logging.getLogger("facing_service")

JSON = zenoh.Encoding.APPLICATION_JSON
BLOCK = zenoh.CongestionControl.BLOCK


class Publisher:
    """Runs on its own thread (``run``) until the outbox is closed and empty, or the
    session closes under a blocked put while ``closing`` is set."""

    def __init__(
        self,
        session: zenoh.Session,
        outbox: Outbox,
        ledger: Ledger,
        closing: threading.Event,
        ros: Callable[[], RosPublishers] | None = None,
        declared: bool = False,
    ) -> None:
        self._session = session
        self._outbox = outbox
        self._ledger = ledger
        self._closing = closing
        self._make_ros = ros  # declared on this thread, when it starts
        self._results = ResultPublishers(session) if declared else None

    def run(self) -> None:
        ros = self._make_ros() if self._make_ros is not None else None
        try:
            while True:
                publications = self._outbox.take()
                if not publications and self._outbox.closed:
                    return
                put, result, declared = self._session.put, Kind.RESULT, self._results
                for p in publications:
                    try:
                        if p.kind is result:  # the hot path, inlined: most of what is sent
                            if declared is None:  # (a wrapper cost 55 ns a result more)
                                put(p.key, p.payload, encoding=JSON, congestion_control=BLOCK)
                            else:
                                declared.put(p.key, p.payload)
                        else:
                            self._send(p, ros)
                        self._ledger.count_sent(p.kind)
                    except zenoh.ZError:
                        if self._closing.is_set():
                            return  # the session closed under a blocked put: shutting down
                        log.exception("publisher: could not publish on %s", p.key)
                        self._ledger.count_sent(None)
                    self._outbox.sent()  # after counting: depth 0 means every count is in
        finally:
            if self._results is not None:
                self._results.close()
            if ros is not None:
                ros.close()

    def _send(self, p: Publication, ros: RosPublishers | None) -> None:
        if p.kind is Kind.ROS:  # the robot's own topics (--output ros2)
            assert ros is not None and p.typename is not None
            ros.send(RosMessage(p.key, p.typename, p.payload))
        elif p.payload is None:  # Kind.DELETE: the body is lost
            self._session.delete(p.key, congestion_control=BLOCK)
            if self._results is not None:
                self._results.forget(p.key)
        else:
            self._session.put(p.key, p.payload, encoding=JSON, congestion_control=BLOCK)


class ResultPublishers:
    """A declared publisher per result key, the most recently used ``CAPACITY`` kept
    (the others undeclared), forgotten when its body is lost: memory stays bounded."""

    CAPACITY = 4096

    def __init__(self, session: zenoh.Session) -> None:
        self._session = session
        self._publishers: OrderedDict[str, zenoh.Publisher] = OrderedDict()

    def put(self, key: str, payload: bytes | None) -> None:
        publisher = self._publishers.get(key)
        if publisher is None:
            publisher = self._session.declare_publisher(
                key, encoding=JSON, congestion_control=BLOCK
            )
            self._publishers[key] = publisher
            if len(self._publishers) > self.CAPACITY:
                self._publishers.popitem(last=False)[1].undeclare()
        else:
            self._publishers.move_to_end(key)
        publisher.put(payload)

    def forget(self, key: str) -> None:
        publisher = self._publishers.pop(key, None)
        if publisher is not None:
            publisher.undeclare()

    def close(self) -> None:
        for publisher in self._publishers.values():
            publisher.undeclare()
        self._publishers.clear()
