"""The hand-off from zenoh's callback threads to the worker: bounded, in order, and cheap.

``queue.Queue`` takes a lock and signals a condition for every item on both sides; under the
soak the worker spent 11 % of the service's Python time in ``Queue.get``/``get_nowait``
(py-spy --gil). Here a deque carries the items (its append and popleft are atomic), and
the lock is only taken to sleep and to wake a sleeper: the worker takes everything queued
in one go.

Bounded: when ``capacity`` entries wait, ``put`` blocks the calling zenoh thread, which
pushes back through zenoh to the senders (nothing is dropped here); it gives up only when
the service is closing.
"""

from __future__ import annotations

import threading
from collections import deque
from typing import Generic, TypeVar

T = TypeVar("T")


class SideQueue(Generic[T]):
    def __init__(self, capacity: int) -> None:
        self.capacity = capacity
        self._items: deque[T] = deque()
        self._lock = threading.Lock()
        self._arrived = threading.Condition(self._lock)  # the worker sleeps on it
        self._room = threading.Condition(self._lock)  # full: callbacks sleep on it
        self._taker_waiting = False
        self._putters_waiting = 0

    def put(self, item: T, closing: threading.Event) -> bool:
        """Queue ``item``, waiting for room while the queue is full; False (not queued)
        only once ``closing`` is set."""
        if len(self._items) >= self.capacity:
            with self._lock:
                self._putters_waiting += 1
                try:
                    while len(self._items) >= self.capacity:
                        if closing.is_set():
                            return False
                        self._room.wait(0.1)
                finally:
                    self._putters_waiting -= 1
        self._items.append(item)
        if self._taker_waiting:  # read without the lock: see take() for why that is safe
            with self._lock:
                self._arrived.notify()
        return True

    def take(self, timeout: float | None, most: int) -> list[T]:
        """Up to ``most`` items, oldest first; waits up to ``timeout`` (None: until an item
        arrives or ``wake``) when there is none."""
        items = self._items
        if not items:
            with self._lock:
                # The flag is set before the second look: a put that appended after the
                # first look either is seen here, or sees the flag and notifies (it needs
                # the lock, which wait() releases).
                self._taker_waiting = True
                if not items:
                    self._arrived.wait(timeout)
                self._taker_waiting = False
        batch: list[T] = []
        while items and len(batch) < most:
            batch.append(items.popleft())
        if batch and self._putters_waiting:
            with self._lock:
                self._room.notify_all()
        return batch

    def wake(self) -> None:
        """Make a waiting ``take`` return (at shutdown)."""
        with self._lock:
            self._arrived.notify_all()
            self._room.notify_all()

    def __len__(self) -> int:
        return len(self._items)
