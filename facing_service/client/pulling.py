"""Subscriptions whose samples a daemon thread of the client's pulls from zenoh's channel.

zenoh's plain callbacks run on threads of its own that are not daemons: a program that
ends, fails or is interrupted without closing its ``FacingClient`` would never exit
(issue 67). A channel pulled by a daemon thread keeps nothing of the client's alive past
the program's own code, and, like zenoh's callback thread, a slow handler never stalls
the session (the channel holds the samples meanwhile).

Those still open when the interpreter exits are closed by an ``atexit`` hook, before
Python stops its daemon threads: one stopped while zenoh hands it a sample unwinds
through zenoh's native code and aborts the process ("FATAL: exception not rethrown").
"""

from __future__ import annotations

import atexit
import itertools
import logging
import threading
import weakref
from collections.abc import Callable
from typing import Protocol

import zenoh

log = logging.getLogger("facing_service.client")

#: How many samples a subscription holds while its handler is busy (zenoh's own depth).
DEPTH = 256

Subscription = zenoh.Subscriber[zenoh.Handler[zenoh.Sample]]


class Pulled:
    """Subscriptions and the daemon threads that hand their samples to handlers."""

    def __init__(self, name: str) -> None:
        self._name = name
        self._entries: list[tuple[Subscription, threading.Thread]] = []

    def subscribe(
        self,
        session: zenoh.Session,
        key: str,
        handle: Callable[[zenoh.Sample], object],
        *,
        tokens: bool = False,
    ) -> None:
        """Subscribe to ``key`` (``tokens``: to the liveliness tokens there, those already
        declared first); ``handle`` each sample, in order, on a daemon thread, until the
        subscriber is undeclared."""
        channel: zenoh.handlers.FifoChannel[zenoh.Sample] = zenoh.handlers.FifoChannel(DEPTH)
        subscriber = (
            session.liveliness().declare_subscriber(key, channel, history=True)
            if tokens
            else session.declare_subscriber(key, channel)
        )
        thread = threading.Thread(
            target=_pull, args=(subscriber, handle), name=self._name, daemon=True
        )
        thread.start()
        self._entries.append((subscriber, thread))
        close_at_exit(self)

    def close(self) -> None:
        """Undeclare every subscriber (its channel ends, its thread with it) and wait for
        the threads, but never for the calling one (a handler may close the client)."""
        entries, self._entries = self._entries, []
        opened_no_more(self)
        for subscriber, _ in entries:
            subscriber.undeclare()
        for _, thread in entries:
            if thread is not threading.current_thread():
                thread.join(timeout=2.0)


class Closable(Protocol):
    def close(self) -> None: ...


#: What is open (a client, a Pulled), until it is closed: at the latest at exit, newest
#: first (a client before the subscriptions it holds).
_OPEN: weakref.WeakKeyDictionary[Closable, int] = weakref.WeakKeyDictionary()
_opened = itertools.count()


def close_at_exit(thing: Closable) -> None:
    """Close ``thing`` when the program exits, unless ``opened_no_more`` says it was."""
    _OPEN[thing] = next(_opened)


def opened_no_more(thing: Closable) -> None:
    _OPEN.pop(thing, None)


@atexit.register
def _close_at_exit() -> None:
    for thing, _ in sorted(_OPEN.items(), key=lambda kv: -kv[1]):
        thing.close()


def _pull(subscriber: Subscription, handle: Callable[[zenoh.Sample], object]) -> None:
    for sample in subscriber.handler:
        try:
            handle(sample)
        except Exception:  # a bug on one sample must never end the subscription
            log.exception("facing client: could not handle a sample on %s", sample.key_expr)
