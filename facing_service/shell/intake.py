"""What the worker takes in: the hot subscriber's own zenoh channel, and a side queue for
everything else, joined in arrival order by wake-up samples.

Why not a Python callback for every sample: zenoh hands a callback's samples to a Python
thread of its own, which then had to hand each one to the worker. That hop cost 30 us of
the service's 380 us median latency (one pose in flight, relay 225 us) and a thread's CPU.
Here the worker pulls the hot samples (input poses, or a robot's /tf) straight from a
``FifoChannel``, blocking in native code with the GIL released.

Everything else (queries, the robot's other topics) still comes through callbacks, into
a bounded deque (``side_queue.SideQueue``); the callback then puts a *wake-up* on a key the hot
subscription matches, local to this session and marked with a per-process token. The
wake-up lands in the channel behind every sample that arrived before the item, so the
worker handles a query after those samples, as before. The same wake-up, sent by an alarm
thread, ends the wait at the worker's next deadline (expiry, dwell, ROS tick, log).

Bounded: the channel holds ``capacity`` samples; when it is full zenoh's receive thread
waits, which pushes back through zenoh to the senders (nothing is dropped here). A sample
on the wake-up key without the token is an input like any other (the service refuses it
as an invalid key).
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable

import zenoh

from ..contract import keys
from .side_queue import SideQueue
from .threads import daemon_thread

_ITEM, _ALARM = b"i", b"a"  # why a wake-up was sent: a side item, or the alarm


class Intake:
    def __init__(
        self,
        session: zenoh.Session,
        key_expr: str,
        capacity: int,
        closing: threading.Event,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self._session = session
        self._wake_key = keys.wake_key(key_expr)
        self._closed = False
        self._token = os.urandom(16)
        self._closing = closing
        self._clock = clock
        self._side: SideQueue[object] = SideQueue(capacity)
        self._channel = session.declare_subscriber(key_expr, zenoh.handlers.FifoChannel(capacity))
        self._alarm = threading.Condition()
        self._alarm_at: float | None = None
        self._alarm_thread = daemon_thread(self._ring, "facing-alarm")
        self._alarm_thread.start()

    # -- producers (zenoh callbacks, the alarm) ------------------------------------------

    def put(self, item: object) -> None:
        """From a callback: queue ``item`` behind every hot sample received so far. One
        wake-up per item: the worker takes one side item per item wake-up, the oldest, so
        nothing is handled before a sample that arrived before it."""
        if self._side.put(item, self._closing):
            self._wake(_ITEM)

    def _wake(self, why: bytes) -> None:
        if self._closing.is_set():
            return
        try:
            self._session.put(
                self._wake_key,
                b"",
                attachment=self._token + why,
                allowed_destination=zenoh.Locality.SESSION_LOCAL,
            )
        except zenoh.ZError:
            if not self._closing.is_set():
                raise

    def set_alarm(self, at: float | None) -> None:
        """Wake the worker by ``at`` (the clock's time; None: no deadline), unless it is
        woken before. Only an earlier deadline re-arms the alarm (a notify is a thread
        wake-up, which the worker's loop must not pay every turn): a later one leaves the
        armed time, and the worker, woken early for nothing, sets it again."""
        armed = self._alarm_at
        if at is None or (armed is not None and armed <= at):
            return
        with self._alarm:
            self._alarm_at = at
            self._alarm.notify()

    def _ring(self) -> None:
        """The alarm thread. It sends the wake-up *without* holding the alarm's lock: the
        put waits while the channel is full, until the worker drains it, and the worker
        takes that lock to set its next alarm (holding it here deadlocked a flood)."""
        while not self._closing.is_set():
            with self._alarm:
                at = self._alarm_at
                left = None if at is None else at - self._clock()
                if left is None or left > 0:
                    self._alarm.wait(left)
                    continue
                self._alarm_at = None
            self._wake(_ALARM)

    # -- the worker ------------------------------------------------------------------------

    def take(self, most: int) -> tuple[list[object], bool]:
        """What arrived, in order (hot samples and side items), waiting for something;
        and whether that was everything (False: a backlog remains). Raises zenoh.ZError
        once the channel is closed."""
        channel = self._channel.handler
        items: list[object] = []
        sample = channel.recv()
        while True:
            attachment = sample.attachment
            if attachment is None or (why := self._woken_by(attachment.to_bytes())) is None:
                items.append(sample)
            elif why == _ITEM:
                items.extend(self._side.take(0.0, 1))
            if len(items) >= most:
                return items, False
            following = channel.try_recv()
            if following is None:
                return items, True
            sample = following

    def _woken_by(self, attachment: bytes) -> bytes | None:
        token = self._token
        if len(attachment) == len(token) + 1 and attachment.startswith(token):
            return attachment[-1:]
        return None

    @property
    def alive(self) -> bool:
        """Whether the alarm thread runs: without it, a quiet input's deadlines (staleness,
        dwell) never come, so the service's status watches it with its own threads."""
        return self._alarm_thread.is_alive()

    def __len__(self) -> int:
        """Items waiting in the side queue (the channel's depth cannot be read)."""
        return len(self._side)

    def close(self) -> None:
        """Undeclare the hot subscriber (a waiting ``take`` then raises) and stop the alarm.
        Call with ``closing`` set; idempotent."""
        if self._closed:
            return
        self._closed = True
        self._channel.undeclare()
        with self._alarm:
            self._alarm.notify()
        self._side.wake()
        self._alarm_thread.join(timeout=0.5)
