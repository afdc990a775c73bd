"""The worker's turn, driven by hand with zenoh's own samples and a clock moved on by
hand (as benchmarks.hot_path drives it): what a batch of poses calls for, in order, and
the counts the status reads after it."""

from __future__ import annotations

from benchmarks.hot_path import SoakClock, samples, worker_on
from facing_service.shell.outbox import Kind


def test_a_turn_says_each_pose_in_order_and_counts_it(net):
    _, ep = net.service()
    session = net.client(ep)
    taken = samples(session, bodies=3, rounds=2)
    clock = SoakClock()
    with worker_on(session, clock) as (worker, outbox):
        worker.turn(taken)
        said = outbox.take(0)
        results = [p.key for p in said if p.kind is Kind.RESULT]
        assert results == [f"hri/bodies/b{b}/facing/map" for b in range(3)] * 2
        assert [p.kind for p in said].index(Kind.FRAME) > 0  # the aggregate after results
        outbox.sent(len(said))
        assert worker._ledger.decided["samples_accepted"] == 6
        assert worker._ledger.tracked == {"map": 3} and not worker.faults.failing
        worker.turn([])  # nothing new, nothing due: nothing said
        assert outbox.take(0) == []
