"""The worker's inbox: order, batches, the bound and its back-pressure, waking."""

from __future__ import annotations

import threading
import time

from facing_service.shell.side_queue import SideQueue


def test_items_come_out_in_order_in_batches():
    inbox: SideQueue[int] = SideQueue(100)
    never = threading.Event()
    for i in range(10):
        assert inbox.put(i, never)
    assert inbox.take(0, most=4) == [0, 1, 2, 3]
    assert inbox.take(0, most=100) == [4, 5, 6, 7, 8, 9]
    assert inbox.take(0.01, most=100) == [] and len(inbox) == 0


def test_a_waiting_taker_wakes_for_an_item_or_on_wake():
    inbox: SideQueue[str] = SideQueue(10)
    got: list[list[str]] = []
    taker = threading.Thread(target=lambda: got.append(inbox.take(None, most=10)))
    taker.start()
    time.sleep(0.05)
    inbox.put("x", threading.Event())
    taker.join(timeout=2)
    assert got == [["x"]]
    taker = threading.Thread(target=lambda: got.append(inbox.take(None, most=10)))
    taker.start()
    time.sleep(0.05)
    inbox.wake()
    taker.join(timeout=2)
    assert not taker.is_alive() and got[-1] == []


def test_a_full_inbox_holds_the_putter_until_there_is_room_or_closing():
    inbox: SideQueue[int] = SideQueue(2)
    closing = threading.Event()
    inbox.put(1, closing)
    inbox.put(2, closing)
    done: list[bool] = []
    putter = threading.Thread(target=lambda: done.append(inbox.put(3, closing)))
    putter.start()
    time.sleep(0.1)
    assert done == [] and len(inbox) == 2  # back-pressure: nothing dropped, nothing over
    assert inbox.take(0, most=1) == [1]
    putter.join(timeout=2)
    assert done == [True] and inbox.take(0, most=10) == [2, 3]
    inbox.put(4, closing)
    inbox.put(5, closing)
    putter = threading.Thread(target=lambda: done.append(inbox.put(6, closing)))
    putter.start()
    closing.set()
    putter.join(timeout=2)
    assert done[-1] is False and inbox.take(0, most=10) == [4, 5]


def test_many_putters_one_taker_lose_nothing():
    inbox: SideQueue[tuple[int, int]] = SideQueue(64)
    never = threading.Event()
    n, putters = 5000, 4

    def put_all(p: int) -> None:
        for i in range(n):
            inbox.put((p, i), never)

    threads = [threading.Thread(target=put_all, args=(p,)) for p in range(putters)]
    for t in threads:
        t.start()
    seen: list[tuple[int, int]] = []
    while len(seen) < n * putters:
        seen += inbox.take(1.0, most=1024)
    for t in threads:
        t.join()
    for p in range(putters):  # each putter's items in its own order, none missing
        assert [i for q, i in seen if q == p] == list(range(n))
