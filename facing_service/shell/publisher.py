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
from collections.abc import Sequence

import zenoh

from .declared_keys import DeclaredKeys
from .ledger import Ledger
from .outbox import Kind, Outbox, Publication
from .outputs import Output, Sender

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
        outputs: Sequence[Output] = (),
    ) -> None:
        self._session = session
        self._outbox = outbox
        self._ledger = ledger
        self._closing = closing
        self._outputs = outputs  # their senders are declared on this thread, when it starts
        self._keys = keys

    def run(self) -> None:
        senders = {s.kind: s for o in self._outputs if (s := o.sender(self._session)) is not None}
        try:
            while True:
                publications = self._outbox.take()
                if not publications and self._outbox.closed:
                    return
                put, result = self._session.put, Kind.RESULT
                declared, declare = self._keys.exprs, self._keys.declare
                key: zenoh.KeyExpr | str | None
                for p in publications:
                    try:
                        if p.kind is result:  # the hot path, inlined: most of what is sent
                            if (key := declared.get(p.key)) is None:
                                key = declare(p.key, True)
                            put(key, p.payload, encoding=JSON, congestion_control=BLOCK)
                        else:
                            self._send(p, senders)
                        self._ledger.count_sent(p.kind)
                    except zenoh.ZError:
                        if self._closing.is_set():
                            return  # the session closed under a blocked put: shutting down
                        log.exception("publisher: could not publish on %s", p.key)
                        self._ledger.count_sent(None)
                    self._outbox.sent()  # after counting: depth 0 means every count is in
        finally:
            self._keys.close()
            for sender in senders.values():
                sender.close()

    def _send(self, p: Publication, senders: dict[Kind, Sender]) -> None:
        if (sender := senders.get(p.kind)) is not None:  # an output form's own (ROS 2)
            sender.send(p)
        elif p.payload is None:  # Kind.DELETE: the body is lost (or a group dissolved)
            self._session.delete(self._keys.exprs.get(p.key, p.key), congestion_control=BLOCK)
            self._keys.forget(p.key)
        elif p.kind is Kind.ENGAGEMENT:  # per body: on its declared key, as results
            declared = self._keys.exprs.get(p.key)
            key = declared if declared is not None else self._keys.declare(p.key, False)
            self._session.put(key, p.payload, encoding=JSON, congestion_control=BLOCK)
        else:
            self._session.put(p.key, p.payload, encoding=JSON, congestion_control=BLOCK)
