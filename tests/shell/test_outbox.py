import threading
import time

from facing_service.shell.outbox import Kind, Outbox, Publication


def result(key, payload):
    return Publication(key, payload, Kind.RESULT)


def test_everything_is_kept_in_order_below_the_limit():
    box = Outbox(limit=100)
    for i in range(5):
        box.add([result("r/a", str(i).encode())])
    box.add([Publication("f", b"agg", Kind.FRAME)])
    taken = [(p.key, p.payload, p.kind.value) for p in box.take()]
    assert taken == [("r/a", str(i).encode(), "result") for i in range(5)] + [
        ("f", b"agg", "frame")
    ]
    assert box.superseded == 0
    assert box.take(timeout=0) == []


def test_past_the_limit_results_conflate_and_move_behind_later_changes():
    box = Outbox(limit=2)
    box.add([result("r/a", b"1")])
    box.add([result("r/a", None)])  # the body was lost: a DELETE, never superseded
    box.add([result("r/a", b"2")])  # and came back: supersedes b"1", goes after the delete
    box.add([result("r/a", b"3")])  # supersedes b"2"
    box.add([result("r/b", b"x")])
    taken = [(p.key, p.payload, p.kind.value) for p in box.take()]
    assert taken == [("r/a", None, "result"), ("r/a", b"3", "result"), ("r/b", b"x", "result")]
    assert box.superseded == 2


def test_changes_never_conflate():
    box = Outbox(limit=10)
    for i in range(1000):
        box.add([Publication("f", str(i).encode(), Kind.FRAME)])
    assert [p.payload for p in box.take()] == [str(i).encode() for i in range(1000)]


def test_stuck_publisher_keeps_memory_bounded_by_limit_plus_bodies():
    box = Outbox(limit=500)
    for i in range(100_000):
        box.add([result(f"r/{i % 100}", str(i).encode())])
    assert len(box) <= 500 + 100
    latest = {p.key: p.payload for p in box.take()}
    assert latest["r/99"] == b"99999" and len(latest) == 100


def test_take_wakes_on_close_and_on_new_items():
    box = Outbox()
    results = []
    reader = threading.Thread(target=lambda: results.append(box.take(timeout=10)))
    reader.start()
    box.add([Publication("f", b"x", Kind.FRAME)])
    reader.join(timeout=5)
    assert results and results[0][0].key == "f"
    reader = threading.Thread(target=lambda: results.append(box.take(timeout=10)))
    reader.start()
    box.close()
    reader.join(timeout=5)
    assert not reader.is_alive() and results[1] == [] and box.closed


def test_depth_counts_taken_publications_until_sent():
    box = Outbox()
    box.add([Publication("f", b"1", Kind.FRAME)])
    box.add([result("r", b"2")])
    taken = box.take()
    assert len(taken) == 2 and len(box) == 2
    box.sent()
    assert len(box) == 1
    box.sent()
    assert len(box) == 0


def test_a_slow_publisher_holds_the_worker_back_and_nothing_is_superseded():
    """Slowness is back-pressure, not loss: only a publisher that stops moving (a put
    blocked on a stuck consumer) lets results conflate."""
    box = Outbox(limit=10, stall_s=0.3)
    got: list[bytes] = []

    def slow_publisher() -> None:
        while True:
            taken = box.take(timeout=5)
            if not taken:
                return
            for p in taken:
                time.sleep(0.002)  # a slow consumer, still reading
                got.append(p.payload)
                box.sent()

    publisher = threading.Thread(target=slow_publisher)
    publisher.start()
    started = time.monotonic()
    for i in range(300):
        box.add([result("r/a", str(i).encode())])
    waited = time.monotonic() - started
    while len(got) < 300 and time.monotonic() - started < 10:
        time.sleep(0.01)
    box.close()
    publisher.join(timeout=5)
    assert box.superseded == 0
    assert got == [str(i).encode() for i in range(300)]
    assert waited > 0.3  # the producer was held back (300 x 2 ms of sending)
