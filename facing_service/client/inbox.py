"""What a client hears: one bounded queue, filled by zenoh without waiting, emptied in order
by one daemon thread of the client's.

zenoh hands each sample straight to a callback on its own network thread
(``Callback(indirect=False)``), which only offers it to the queue and returns: a full
queue drops the sample, counted and logged once per episode, instead of waiting. A zenoh
FIFO channel instead (the client's subscriptions once) blocks zenoh's sender
when it is full, and with it every other subscription, liveliness token and query of the
session: 406 samples to a 20 ms handler delayed an unrelated subscriber by 3 s. One
queue for every subscription keeps the order between streams (a result and the group it
changes arrive as they were sent), and leaves one thread to reason about.

Nothing here is a non-daemon thread (zenoh's plain callbacks run on threads of their own
that are: a program that ends without closing its client would never exit).
What is still open when the interpreter exits is closed by an ``atexit`` hook, before
Python stops its daemon threads: one stopped while zenoh hands it a sample unwinds
through zenoh's native code and aborts the process ("FATAL: exception not rethrown").
"""

from __future__ import annotations

import atexit
import contextlib
import itertools
import logging
import queue
import threading
import weakref
from collections.abc import Callable
from typing import Protocol

import zenoh

log = logging.getLogger("facing_service.client")

#: Samples waiting for the client's thread: about four seconds of 20 people's results at
#: 30 Hz, far more than a thread that only decodes and files them ever lets pile up.
DEPTH = 4096

Handle = Callable[[zenoh.Sample], object]
Subscription = zenoh.Subscriber[None]


class Overflow:
    """A count of what a bounded queue refused, logged in one line when it starts and
    one when it ends (a count per episode, not a line per item): an episode ends when
    the queue has emptied, not when one item has gone (under sustained overload a slot
    frees and fills again with every item)."""

    def __init__(self, what: str) -> None:
        self._what = what
        self._lock = threading.Lock()
        self.dropped = 0  # ever
        self._episode = 0  # since the queue last had room

    def refused(self) -> None:
        with self._lock:
            self.dropped += 1
            self._episode += 1
            first = self._episode == 1
        if first:
            log.warning("facing client: %s; dropping until it catches up", self._what)

    def emptied(self) -> None:
        """The queue has caught up with everything it held: the episode, if any, ends."""
        if not self._episode:  # a plain read: the common case costs no lock
            return
        with self._lock:
            episode, self._episode = self._episode, 0
        if episode:
            log.warning("facing client: caught up after dropping %d (%s)", episode, self._what)


class Serial:
    """Calls run one after another, in the order offered, on one daemon thread; offered
    without waiting: past ``depth`` waiting, a call is dropped, counted and logged."""

    def __init__(self, name: str, depth: int, falling_behind: str) -> None:
        self._queue: queue.Queue[tuple[Callable[..., object], tuple[object, ...]] | None] = (
            queue.Queue(depth)
        )
        self.overflow = Overflow(falling_behind)
        self._stopped = threading.Event()
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    @property
    def dropped(self) -> int:
        """Calls offered while the queue was full, never run."""
        return self.overflow.dropped

    def offer(self, call: Callable[..., object], *args: object) -> None:
        try:
            self._queue.put_nowait((call, args))
        except queue.Full:
            self.overflow.refused()

    def stop(self) -> None:
        """Run nothing more; wait for the call under way, unless this is its thread (a
        callback may close the client)."""
        self._stopped.set()
        with contextlib.suppress(queue.Full):  # full: the thread wakes to the next item
            self._queue.put_nowait(None)
        if self._thread is not threading.current_thread():
            self._thread.join(timeout=2.0)

    def _run(self) -> None:
        while not self._stopped.is_set() and (item := self._queue.get()) is not None:
            call, args = item
            try:
                call(*args)
            except BaseException:  # one bug, one bad sample, or a callback's sys.exit()
                # must never end the thread: the cache would freeze without a word
                about = next((f" on {a.key_expr}" for a in args if isinstance(a, zenoh.Sample)), "")
                log.exception("facing client: could not handle %s%s", _name(call), about)
            if self._queue.empty():
                self.overflow.emptied()


def _name(call: Callable[..., object]) -> str:
    return str(getattr(call, "__name__", call))


class Inbox(Serial):
    """Subscriptions whose samples one daemon thread hands to their handlers, in the order
    zenoh delivered them across all of them."""

    def __init__(self, name: str, depth: int = DEPTH) -> None:
        super().__init__(name, depth, f"{name} falls behind what it hears")
        self._subscribers: list[Subscription] = []
        self._lock = threading.Lock()  # the subscribers' list: declared from two threads
        close_at_exit(self)

    def subscribe(
        self, session: zenoh.Session, key: str, handle: Handle, *, tokens: bool = False
    ) -> None:
        """Subscribe to ``key`` (``tokens``: to the liveliness tokens there, those already
        declared first) and ``handle`` each sample on the inbox's thread."""

        def offer(sample: zenoh.Sample) -> None:  # on zenoh's thread: never waits
            self.offer(handle, sample)

        callback = zenoh.handlers.Callback(offer, indirect=False)
        subscriber = (
            session.liveliness().declare_subscriber(key, callback, history=True)
            if tokens
            else session.declare_subscriber(key, callback)
        )
        with self._lock:
            self._subscribers.append(subscriber)

    def close(self) -> None:
        """Undeclare every subscriber (nothing more is offered), then stop the thread."""
        opened_no_more(self)
        with self._lock:
            subscribers, self._subscribers = self._subscribers, []
        for subscriber in subscribers:
            subscriber.undeclare()
        self.stop()


class Closable(Protocol):
    def close(self) -> None: ...


#: What is open (a client, an inbox), until it is closed: at the latest at exit, newest
#: first (a client before the inbox it holds).
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
