"""The publisher thread: sends what the outbox holds, in order, through each output's own
sender (JSON or the robot's CDR: this thread only moves their bytes).

It is the only thread that waits on the network. A slow consumer slows it down; one that
stops reading blocks it (up to zenoh's ``wait_before_close``: our JSON keys go out with
BLOCK), while the worker keeps ingesting, deciding and answering (see ``outbox``).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Sequence

import zenoh

from .ledger import Ledger
from .outbox import Kind, Outbox, Publication
from .outputs import Output

log = logging.getLogger("facing_service")


class Publisher:
    """Runs on its own thread (``run``) until the outbox is closed and empty, or the
    session closes under a blocked put while ``closing`` is set."""

    def __init__(
        self,
        session: zenoh.Session,
        outbox: Outbox,
        ledger: Ledger,
        closing: threading.Event,
        outputs: Sequence[Output] = (),
    ) -> None:
        self._session = session
        self._outbox = outbox
        self._ledger = ledger
        self._closing = closing
        self._outputs = outputs  # their senders are declared on this thread, when it starts

    def run(self) -> None:
        senders = [output.sender(self._session) for output in self._outputs]
        send: dict[Kind, Callable[[Publication], None]] = {
            kind: sender.send for sender in senders for kind in sender.kinds
        }
        try:
            while True:
                publications = self._outbox.take()
                if not publications and self._outbox.closed:
                    return
                for p in publications:
                    try:
                        send[p.kind](p)
                        self._ledger.count_sent(p)
                    except zenoh.ZError:
                        if self._closing.is_set():
                            return  # the session closed under a blocked put: shutting down
                        log.exception("publisher: could not publish on %s", p.key)
                        self._ledger.count_sent(None)
                    self._outbox.sent()  # after counting: depth 0 means every count is in
        finally:
            for sender in senders:
                sender.close()
