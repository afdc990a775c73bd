"""The worker's hot path alone, without the network: what one turn costs a pose, by the
size of the batch it took.

    python -m benchmarks.perf.hot_path [--bodies 100] [--rounds 60] [--batches 1,20,100]

Real zenoh samples (put on a local session, taken from a ``FifoChannel`` as the intake
takes them) go through ``Worker.turn``: the input's read, the tracker, the outputs'
publications, expiry, the scenes and the hand-over to the outbox, drained each turn as
the publisher would. The clock is the soak's (``--hz`` poses a body a second): each turn
moves it by the time its poses took to arrive, so the scenes and periodic messages tick
as they do live. Printed: µs a pose (best of ``--repeat``) and, with ``--profile``, where
a turn's time goes. The grid measures the whole process; this splits the worker's share.
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

import zenoh

from facing_service.config.settings import Settings
from facing_service.contract import keys
from facing_service.shell.compose import answers_for, parts_for
from facing_service.shell.decisions import Decisions
from facing_service.shell.intake import Intake
from facing_service.shell.ledger import Ledger
from facing_service.shell.outbox import Outbox
from facing_service.shell.service import INBOX_SIZE
from facing_service.shell.worker import Worker
from facing_service.tools.loopback import loopback_config

from .common import pose_payload


def samples(session: zenoh.Session, bodies: int, rounds: int) -> list[zenoh.Sample]:
    """``rounds`` poses of each body, stamps increasing, as zenoh hands them over."""
    expected = bodies * rounds
    channel = session.declare_subscriber(
        keys.pose_subscription("hri", "map"), zenoh.handlers.FifoChannel(expected + 1)
    )
    try:
        for r in range(rounds):
            for b in range(bodies):
                yaw = 180.0 + (b % 7) * 5.0 + (r % 5)  # some face the robot, some turn
                payload = pose_payload(f"b{b}", "map", 1.0 + b % 4, 0.1 * (b % 9), yaw, 1 + r)
                session.put(keys.pose_key("hri", body_id=f"b{b}", frame_id="map"), payload)
        taken: list[zenoh.Sample] = []
        deadline = time.monotonic() + 10
        while len(taken) < expected and time.monotonic() < deadline:
            sample = channel.handler.try_recv()
            if sample is None:
                time.sleep(0.001)
            else:
                taken.append(sample)
        if len(taken) < expected:
            raise SystemExit(f"only {len(taken)} of {expected} samples came back")
        return taken
    finally:
        channel.undeclare()


class SoakClock:
    """The service's clock in the soak: moved on by hand, as the poses arrive."""

    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


@contextmanager
def worker_on(session: zenoh.Session, clock: SoakClock) -> Iterator[tuple[Worker, Outbox]]:
    """A worker as the service makes it (default settings, JSON input and output)."""
    settings = Settings(base_frame="map")
    ledger = Ledger(clock)
    parts = parts_for(settings, ledger, clock)
    closing = threading.Event()
    intake = Intake(session, parts.source.hot_key(), INBOX_SIZE, closing, clock)
    outbox = Outbox()
    decisions = Decisions(parts, ledger, outbox)
    worker = Worker(decisions, intake, answers_for(settings, ledger), clock, closing)
    try:
        yield worker, outbox
    finally:
        closing.set()
        intake.close()


def run_through(worker: Worker, outbox: Outbox, taken: list[zenoh.Sample], batch: int,
                clock: SoakClock, hz: float, bodies: int) -> float:  # fmt: skip
    """Seconds of CPU the worker's turns took for all of ``taken``, in turns of ``batch``."""
    step = 1.0 / (hz * bodies)
    spent = 0.0
    for start in range(0, len(taken), batch):
        chunk = taken[start : start + batch]
        clock.now += step * len(chunk)
        began = time.process_time()
        worker.turn(chunk)
        spent += time.process_time() - began
        outbox.take(0)
        outbox.sent(len(outbox))
    return spent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bodies", type=int, default=100)
    parser.add_argument("--rounds", type=int, default=60)
    parser.add_argument("--hz", type=float, default=30.0)
    parser.add_argument("--batches", default="1,20,100")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--profile", type=int, default=0, help="profile turns of this size")
    args = parser.parse_args()
    with zenoh.open(loopback_config()) as session:
        taken = samples(session, args.bodies, args.rounds)
        for batch in (int(b) for b in args.batches.split(",")):
            best = float("inf")
            for _ in range(args.repeat):
                clock = SoakClock()
                with worker_on(session, clock) as (worker, outbox):
                    spent = run_through(worker, outbox, taken, batch, clock, args.hz, args.bodies)
                best = min(best, spent)
            print(f"batch {batch:5d}: {1e6 * best / len(taken):6.2f} us a pose", flush=True)
        if args.profile:
            clock = SoakClock()
            with worker_on(session, clock) as (worker, outbox):
                profile = cProfile.Profile()
                profile.enable()
                run_through(worker, outbox, taken, args.profile, clock, args.hz, args.bodies)
                profile.disable()
            pstats.Stats(profile).sort_stats("tottime").print_stats(25)


if __name__ == "__main__":
    main()
