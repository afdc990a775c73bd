"""The client's inbox over real zenoh sessions: what it hears never holds zenoh's threads,
keeps the order between its subscriptions, and what it cannot keep is counted."""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Iterator

import pytest
import zenoh

from facing_service.client.inbox import Inbox, Serial
from facing_service.testing import loopback_config

from loopback import endpoint, free_port, wait_until

FLOOD = 600  # more than zenoh's FIFO of 256 held: a blocking channel stalls the session


@pytest.fixture
def pair() -> Iterator[tuple[zenoh.Session, zenoh.Session]]:
    """Two peers on loopback: one that hears, one that sends."""
    ep = endpoint(free_port())
    with (
        zenoh.open(loopback_config(listen=[ep])) as heard,
        zenoh.open(loopback_config(connect=[ep])) as sender,
    ):
        yield heard, sender


def _put_until(sender: zenoh.Session, key: str, heard: list) -> None:
    """Put on ``key`` until ``heard`` has something (the peers meet first), then empty it."""

    def put_and_look() -> bool:
        sender.put(key, b"probe")
        time.sleep(0.05)
        return bool(heard)

    wait_until(put_and_look, 10, f"{key} heard")
    time.sleep(0.2)  # the last probes in flight
    heard.clear()


def test_a_slow_handler_never_holds_an_unrelated_subscriber_of_the_session(pair):
    """406 samples to a 20 ms handler held an unrelated subscriber's sample for 3 s when
    the client's subscriptions were zenoh FIFO channels (full at 256: zenoh's sender then
    waits, and every other subscription of the session with it). The unrelated sample
    must come while the slow handler has handled a fraction of the flood, not after it."""
    heard, sender = pair
    handled = []
    other_heard_at: list[int] = []
    inbox = Inbox("test-inbox")
    try:
        inbox.subscribe(heard, "t/flood", lambda _: (time.sleep(0.02), handled.append(1)))
        other = heard.declare_subscriber("t/other", lambda _: other_heard_at.append(len(handled)))
        try:
            _put_until(sender, "t/flood", handled)
            _put_until(sender, "t/other", other_heard_at)
            block = zenoh.CongestionControl.BLOCK
            for i in range(FLOOD):
                sender.put("t/flood", str(i), congestion_control=block)
            sender.put("t/other", b"now", congestion_control=block)
            wait_until(lambda: other_heard_at, 30, "the other sample")
        finally:
            other.undeclare()
    finally:
        inbox.close()
    # at 20 ms a sample, the flood takes 12 s: the other sample came with a few handled
    assert other_heard_at[0] < FLOOD // 4, other_heard_at
    assert inbox.dropped == 0  # 600 fit in the inbox: nothing lost, only late


def test_the_order_between_subscriptions_is_the_order_heard(pair):
    """One queue for every subscription: samples of two keys, interleaved by one sender,
    are handled interleaved as sent (one pulling thread per subscription lost that)."""
    heard, sender = pair
    order: list[str] = []
    inbox = Inbox("test-inbox")
    try:
        inbox.subscribe(heard, "t/a", lambda s: order.append(s.payload.to_string()))
        inbox.subscribe(heard, "t/b", lambda s: order.append(s.payload.to_string()))
        _put_until(sender, "t/a", order)
        _put_until(sender, "t/b", order)
        sent = [f"{'ab'[i % 2]}{i}" for i in range(200)]
        for item in sent:
            sender.put(f"t/{item[0]}", item, congestion_control=zenoh.CongestionControl.BLOCK)
        wait_until(lambda: len(order) >= len(sent), 10, "every sample")
    finally:
        inbox.close()
    assert order == sent


def test_what_does_not_fit_is_dropped_counted_and_said_once(caplog):
    """A queue full of calls drops the next ones, counts each, says it once when it
    starts and once when it catches up, and runs what it kept in order."""
    release = threading.Event()
    ran: list[int] = []
    calls = Serial("test-calls", 3, "the test's calls fall behind")
    try:
        calls.offer(release.wait)
        wait_until(lambda: calls._queue.empty(), 5, "the calls")  # the first call under way
        for i in range(10):
            calls.offer(ran.append, i)
        assert calls.dropped == 7
        release.set()
        wait_until(lambda: len(ran) == 3, 5, "the calls")
        calls.offer(ran.append, 10)
        wait_until(lambda: len(ran) == 4, 5, "the calls")
    finally:
        calls.stop()
    assert ran == [0, 1, 2, 10]
    said = [r.getMessage() for r in caplog.records if "fall behind" in r.getMessage()]
    assert said == [
        "facing client: the test's calls fall behind; dropping until it catches up",
        "facing client: caught up after dropping 7 (the test's calls fall behind)",
    ]


def test_a_sustained_overload_is_one_episode_said_once(caplog):
    """Before: "dropping" and "caught up" alternated on every item (a slot freed by one
    call ended the episode, the next offer started another: 1 532 lines for 772 drops in
    2 s), and the test above passed because its queue emptied at once."""
    turns = threading.Semaphore(0)
    calls = Serial("test-calls", 3, "the test's calls fall behind")
    try:
        calls.offer(turns.acquire)
        wait_until(lambda: calls._queue.empty(), 5, "the first call under way")
        for _ in range(50):  # the queue kept full: each call that ends frees one slot
            while calls._queue.qsize() < 3:
                calls.offer(turns.acquire)
            calls.offer(turns.acquire)  # dropped
            turns.release()
            wait_until(lambda: calls._queue.qsize() < 3, 5, "a call ended")
        for _ in range(60):
            turns.release()
        wait_until(lambda: calls._queue.empty(), 5, "caught up")
        wait_until(lambda: calls.overflow._episode == 0, 5, "the episode said ended")
    finally:
        calls.stop()
    said = [r.getMessage() for r in caplog.records if "fall behind" in r.getMessage()]
    assert said == [
        "facing client: the test's calls fall behind; dropping until it catches up",
        "facing client: caught up after dropping 50 (the test's calls fall behind)",
    ], said[:6]


def test_a_callback_that_exits_does_not_end_the_thread(caplog):
    """Before: a callback raising SystemExit (sys.exit() in a behaviour) ended the
    client's thread without a word, and its cache froze."""
    ran: list[int] = []
    calls = Serial("test-calls", 8, "behind")
    try:
        calls.offer(sys.exit, 3)
        calls.offer(ran.append, 1)
        wait_until(lambda: ran == [1], 5, "the call after the exit")
    finally:
        calls.stop()
    assert any("could not handle exit" in r.getMessage() for r in caplog.records)


def test_a_call_may_stop_its_own_thread_even_with_a_full_queue():
    """A callback closing the client while calls wait: no deadlock, the rest not run."""
    ran: list[int] = []
    calls = Serial("test-calls", 2, "behind")
    gate = threading.Event()
    calls.offer(gate.wait)
    wait_until(lambda: calls._queue.empty(), 5, "the calls")
    calls.offer(calls.stop)
    calls.offer(ran.append, 1)
    gate.set()
    wait_until(lambda: not calls._thread.is_alive(), 5, "the calls")
    assert ran == []
