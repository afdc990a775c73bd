"""The publisher thread: sends what the outbox holds, in order, every output with BLOCK.

It is the only thread that waits on the network. A slow consumer slows it down; one that
stops reading blocks it (up to zenoh's ``wait_before_close``), while the worker keeps
ingesting, deciding and answering (see ``outbox``).

Per-body results and engagement go out through ``Session.put`` on key expressions
declared per body (``declared_keys``: zenoh then routes them, and the poses they answer,
from its cache).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

import zenoh

from ..ros2.output import RosMessage
from .declared_keys import DeclaredKeys
from .ledger import Ledger
from .outbox import Kind, Outbox, Publication
from .ros_bus import RobotPublishers

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
        keys: DeclaredKeys,
        ros: Callable[[], RobotPublishers] | None = None,
    ) -> None:
        self._session = session
        self._outbox = outbox
        self._ledger = ledger
        self._closing = closing
        self._make_ros = ros  # declared on this thread, when it starts
        self._keys = keys

    def run(self) -> None:
        ros = self._make_ros() if self._make_ros is not None else None
        try:
            while True:
                publications = self._outbox.take()
                if not publications and self._outbox.closed:
                    return
                put, result = self._session.put, Kind.RESULT
                declared, declare = self._keys.exprs, self._keys.declare
                for p in publications:
                    try:
                        if p.kind is result:  # the hot path, inlined: most of what is sent
                            if (key := declared.get(p.key)) is None:
                                key = declare(p.key, True)
                            put(key, p.payload, encoding=JSON, congestion_control=BLOCK)
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
            self._keys.close()
            if ros is not None:
                ros.close()

    def _send(self, p: Publication, ros: RobotPublishers | None) -> None:
        if p.kind is Kind.ROS:  # the robot's own topics (--output ros2)
            assert ros is not None and p.typename is not None
            ros.send(RosMessage(p.key, p.typename, p.payload))
        elif p.payload is None:  # Kind.DELETE: the body is lost (or a group dissolved)
            key = self._keys.exprs.get(p.key, p.key)
            self._session.delete(key, congestion_control=BLOCK)
            self._keys.forget(p.key)
        elif p.kind is Kind.ENGAGEMENT:  # per body: on its declared key, as results
            if (key := self._keys.exprs.get(p.key)) is None:
                key = self._keys.declare(p.key, False)
            self._session.put(key, p.payload, encoding=JSON, congestion_control=BLOCK)
        else:
            self._session.put(p.key, p.payload, encoding=JSON, congestion_control=BLOCK)
