"""The worker's intake on a real zenoh session: hot samples and side items in arrival
order, the alarm, tokenless wake-up keys, and shutdown."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator

import pytest
import zenoh

from facing_service.contract.keys import wake_key
from facing_service.shell.intake import Intake
from facing_service.testing import loopback_config

HOT = "hri/bodies/*/pose/cam"


@pytest.fixture
def session() -> Iterator[zenoh.Session]:
    with zenoh.open(loopback_config()) as s:
        yield s


@pytest.fixture
def intake(session: zenoh.Session) -> Iterator[tuple[Intake, threading.Event]]:
    closing = threading.Event()
    box = Intake(session, HOT, 64, closing)
    yield box, closing
    closing.set()
    box.close()


def keys_of(items: list[object]) -> list[str]:
    return [str(i.key_expr) if isinstance(i, zenoh.Sample) else str(i) for i in items]


def take_all(box: Intake, n: int) -> list[object]:
    got: list[object] = []
    while len(got) < n:
        items, _ = box.take(100)
        got += items
    return got


def test_side_items_come_after_the_samples_that_arrived_before_them(session, intake):
    box, _ = intake
    session.put("hri/bodies/a/pose/cam", b"1")
    box.put("query-1")
    session.put("hri/bodies/b/pose/cam", b"2")
    session.put("hri/bodies/c/pose/cam", b"3")
    box.put("query-2")
    box.put("query-3")
    session.put("hri/bodies/d/pose/cam", b"4")
    assert keys_of(take_all(box, 7)) == [
        "hri/bodies/a/pose/cam",
        "query-1",
        "hri/bodies/b/pose/cam",
        "hri/bodies/c/pose/cam",
        "query-2",
        "query-3",
        "hri/bodies/d/pose/cam",
    ]
    assert len(box) == 0


def test_the_alarm_ends_a_wait_at_the_deadline_with_nothing(intake):
    box, _ = intake
    box.set_alarm(time.monotonic() + 0.2)
    started = time.monotonic()
    items, drained = box.take(100)
    assert items == [] and drained
    assert 0.15 < time.monotonic() - started < 2.0
    box.set_alarm(time.monotonic() + 60)  # a later deadline does not push an earlier one
    box.set_alarm(time.monotonic() + 0.1)
    started = time.monotonic()
    assert box.take(100)[0] == []
    assert time.monotonic() - started < 2.0


def test_the_wake_up_key_without_the_token_is_an_input_like_any_other(session, intake):
    box, _ = intake
    key = wake_key(HOT)
    assert key == "hri/bodies/~wake/pose/cam"
    session.put(key, b"forged", attachment=b"not the token")
    session.put(key, b"plain")
    items = take_all(box, 2)
    assert keys_of(items) == [key, key]
    assert [i.payload.to_bytes() for i in items] == [b"forged", b"plain"]


def test_a_backlog_is_reported_and_taken_in_order(session, intake):
    box, _ = intake
    for i in range(30):
        session.put(f"hri/bodies/b{i}/pose/cam", b"x")
    time.sleep(0.1)
    first, drained = box.take(10)
    assert len(first) == 10 and not drained
    rest = take_all(box, 20)
    assert keys_of(first + rest) == [f"hri/bodies/b{i}/pose/cam" for i in range(30)]


def test_closing_ends_a_waiting_take(intake):
    box, closing = intake
    errors: list[BaseException] = []

    def wait() -> None:
        try:
            box.take(100)
        except zenoh.ZError as error:
            errors.append(error)

    taker = threading.Thread(target=wait)
    taker.start()
    time.sleep(0.1)
    closing.set()
    box.close()
    box.close()  # idempotent
    taker.join(timeout=2)
    assert not taker.is_alive() and errors


def test_an_alarm_firing_into_a_full_channel_does_not_block_the_worker(session):
    """The alarm's wake-up waits while the channel is full; the worker, setting its next
    alarm before draining, must not wait on the alarm meanwhile (a flood once deadlocked
    the two)."""
    closing = threading.Event()
    box = Intake(session, HOT, 4, closing)
    flood = threading.Thread(
        target=lambda: [session.put(f"hri/bodies/b{i}/pose/cam", b"x") for i in range(50)]
    )
    try:
        flood.start()
        box.set_alarm(time.monotonic() + 0.05)  # fires while the channel is full
        time.sleep(0.3)
        got: list[object] = []

        def worker() -> None:
            while len(got) < 50:
                box.set_alarm(time.monotonic() + 10)
                got.extend(i for i in box.take(100)[0] if isinstance(i, zenoh.Sample))

        draining = threading.Thread(target=worker, daemon=True)
        draining.start()
        draining.join(timeout=10)
        assert not draining.is_alive(), "the worker is stuck behind the alarm"
        assert len(got) == 50
    finally:
        flood.join(timeout=5)
        closing.set()
        box.close()
