"""The worker's turn, driven by hand with zenoh's own samples and a clock moved on by
hand (as benchmarks.perf.hot_path drives it, built here as the service builds it): what a
batch of poses calls for, in order, and the counts the status reads after it."""

from __future__ import annotations

import itertools
import threading

import zenoh

from facing_service.config.settings import Settings
from facing_service.contract import keys
from facing_service.shell.compose import answers_for, parts_for
from facing_service.shell.decisions import Decisions
from facing_service.shell.intake import Intake
from facing_service.shell.ledger import Ledger
from facing_service.shell.outbox import Kind, Outbox
from facing_service.shell.service import INBOX_SIZE
from facing_service.shell.worker import Worker

from poses import pose_json


def zenoh_samples(session: zenoh.Session, bodies: int, rounds: int) -> list[zenoh.Sample]:
    """``rounds`` poses of each body (facing the robot, 2 m ahead), as zenoh hands them
    over to a subscriber."""
    channel = session.declare_subscriber(
        keys.pose_subscription("hri", "map"), zenoh.handlers.FifoChannel(bodies * rounds + 1)
    )
    try:
        for sec in range(1, rounds + 1):
            for b in range(bodies):
                pose = pose_json(f"b{b}", "map", x=2.0, y=0.0, sec=sec)
                session.put(keys.pose_key("hri", body_id=f"b{b}", frame_id="map"), pose)
        return [channel.handler.recv() for _ in range(bodies * rounds)]  # (per-test timeout)
    finally:
        channel.undeclare()


def test_a_turn_says_each_pose_in_order_and_counts_it(net):
    _, ep = net.service()
    session = net.client(ep)
    taken = zenoh_samples(session, bodies=3, rounds=2)
    settings, closing = Settings(base_frame="map"), threading.Event()
    clock = itertools.repeat(1000.0).__next__  # a clock that stands still: nothing falls due
    ledger = Ledger(clock)
    parts = parts_for(settings, ledger, clock)
    intake = Intake(session, parts.source.hot_key(), INBOX_SIZE, closing, clock)
    outbox = Outbox()
    worker = Worker(
        Decisions(parts, ledger, outbox), intake, answers_for(settings, ledger), clock, closing
    )
    try:
        worker.turn(taken)
        said = outbox.take(0)
        results = [p.key for p in said if p.kind is Kind.RESULT]
        assert results == [f"hri/bodies/b{b}/facing/map" for b in range(3)] * 2
        assert [p.kind for p in said].index(Kind.FRAME) > 0  # the aggregate after results
        outbox.sent(len(said))
        assert ledger.decided["samples_accepted"] == 6
        assert ledger.tracked == {"map": 3} and not worker.faults.failing
        worker.turn([])  # nothing new, nothing due: nothing said
        assert outbox.take(0) == []
    finally:
        closing.set()
        intake.close()
