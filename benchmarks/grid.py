"""The grid of issue 36: how the tracker connects (peer, client), how it publishes
(``Session.put``, declared publishers) and who consumes (nobody, the per-body results,
everything under the namespace), each cell's service CPU (with each
``--result-publishers``) against the cheapest bare relay for that same cell, measured in
the same run.

    python -m benchmarks.grid             # 100 bodies x 30 Hz for 6 s a cell (about 4 min)
    python -m benchmarks.grid --quick     # two cells, small: what CI runs so this never rots

The consumer runs on the tracker's own session (as the outside scripts in ../shared/bench
do), so a client-mode tracker's results come back over its one link. Each target is its
own process (``benchmarks.relay``, or the service through its CLI), CPU from /proc over
the stream; every result must arrive when someone consumes them. Latency, bursts and the
flood are ``python -m benchmarks``'s; this grid is the CPU its three outside scripts
disagreed on.
"""

from __future__ import annotations

import argparse
import itertools
import json
import time
from pathlib import Path
from typing import Any

import zenoh

from facing_service.contract import keys
from facing_service.testing import endpoint, free_port, loopback_config

from .__main__ import start, wait_ready
from .common import pose_payload
from .driver import cpu_seconds

MODES = ("peer", "client")
STYLES = ("put", "publishers")
CONSUMERS = ("none", "results", "everything")
TARGETS = ("relay_put", "relay_publishers", "service", "service-declared")
SERVICES = TARGETS[2:]  # the service with each --result-publishers
FRAME = "cam"
BLOCK = zenoh.CongestionControl.BLOCK
JSON = zenoh.Encoding.APPLICATION_JSON


def stream(
    target: str, mode: str, style: str, consumer: str, bodies: int, hz: float, seconds: float
) -> dict[str, Any]:
    """One target in one cell: the CPU it spent on ``bodies`` x ``hz`` for ``seconds``."""
    port = free_port()
    with start(target, port) as proc, _open(port, mode) as session:
        wait_ready(session)
        received = [0]
        wanted = {
            "none": None,
            "results": keys.facing_key("hri", "*", FRAME),
            "everything": "hri/**",
        }[consumer]
        subscriber = None
        if wanted is not None:

            def count(sample: zenoh.Sample) -> None:
                if sample.kind == zenoh.SampleKind.PUT and "/facing/" in str(sample.key_expr):
                    received[0] += 1

            subscriber = session.declare_subscriber(wanted, count)
        publishers: dict[str, zenoh.Publisher] = {}

        def put(key: str, payload: bytes) -> None:
            if style == "put":
                session.put(key, payload, encoding=JSON, congestion_control=BLOCK)
                return
            if (publisher := publishers.get(key)) is None:
                publisher = publishers[key] = session.declare_publisher(
                    key, encoding=JSON, congestion_control=BLOCK
                )
            publisher.put(payload)

        names = [f"b{i:04d}" for i in range(bodies)]
        try:
            for name in names:  # every key known (and declared) before the measure
                put(keys.pose_key("hri", name, FRAME), pose_payload(name, FRAME, 2, 0.3, 171, 1))
            time.sleep(1.0)
            first = received[0]
            before, start_s = cpu_seconds(proc.pid), time.perf_counter()
            rounds = max(1, round(seconds * hz))
            for r in range(rounds):
                for name in names:
                    payload = pose_payload(name, FRAME, 2, 0.3, 171, 10 + r)
                    put(keys.pose_key("hri", name, FRAME), payload)
                time.sleep(max(0.0, start_s + (r + 1) / hz - time.perf_counter()))
            sent = rounds * bodies
            deadline = time.monotonic() + 10
            while wanted is not None and received[0] - first < sent:
                if time.monotonic() > deadline:
                    break
                time.sleep(0.05)
            time.sleep(0.5)  # the last results on their way out
            cpu = cpu_seconds(proc.pid) - before
        finally:
            if subscriber is not None:
                subscriber.undeclare()
            for publisher in publishers.values():
                publisher.undeclare()
    lost = 0 if wanted is None else sent - (received[0] - first)
    return {"cpu_s": cpu, "us_per_pose": cpu / sent * 1e6, "sent": sent, "lost": lost}


def _open(port: int, mode: str) -> zenoh.Session:
    """The tracker's session; a client fails at once while its target is not listening
    yet (a peer would retry by itself), so it is opened again until it connects."""
    deadline = time.monotonic() + 20
    while True:
        try:
            return zenoh.open(loopback_config(connect=[endpoint(port)], mode=mode))
        except zenoh.ZError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.1)


def run(cells: list[tuple[str, str, str]], bodies: int, hz: float, seconds: float) -> list[dict]:
    out = []
    for mode, style, consumer in cells:
        figures = {t: stream(t, mode, style, consumer, bodies, hz, seconds) for t in TARGETS}
        cheapest = min(TARGETS[:2], key=lambda t: figures[t]["cpu_s"])
        relay = figures[cheapest]["cpu_s"]
        out.append(
            {
                "mode": mode,
                "style": style,
                "consumer": consumer,
                "targets": figures,
                "cheapest_relay": cheapest,
                "cpu_ratio": {  # None: below the clock's tick (--quick's sizes)
                    s: figures[s]["cpu_s"] / relay if relay > 0 else None for s in SERVICES
                },
            }
        )
        print(line(out[-1]), flush=True)
    return out


def line(cell: dict) -> str:
    t = cell["targets"]
    return (
        f"{cell['mode']:6} {cell['style']:10} {cell['consumer']:10} "
        f"relay put {t['relay_put']['us_per_pose']:6.1f}  relay publishers "
        f"{t['relay_publishers']['us_per_pose']:6.1f}  service put "
        f"{t['service']['us_per_pose']:6.1f} {_ratio(cell['cpu_ratio']['service'])}  declared "
        f"{t['service-declared']['us_per_pose']:6.1f} "
        f"{_ratio(cell['cpu_ratio']['service-declared'])} (us/pose, ratio to "
        f"{cell['cheapest_relay']})  lost {sum(t[s]['lost'] for s in SERVICES)}"
    )


def _ratio(value: float | None) -> str:
    return "  - " if value is None else f"{value:4.2f}"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two cells, small and short")
    parser.add_argument("--out", type=Path, help="write the cells as JSON")
    args = parser.parse_args(argv)
    cells = list(itertools.product(MODES, STYLES, CONSUMERS))
    if args.quick:
        cells = [("peer", "put", "none"), ("client", "publishers", "results")]
        results = run(cells, bodies=10, hz=30.0, seconds=1.0)
    else:
        print(f"{'mode':6} {'style':10} {'consumer':10} service CPU per pose against the relays")
        results = run(cells, bodies=100, hz=30.0, seconds=6.0)
    if args.out is not None:
        args.out.write_text(json.dumps(results, indent=2) + "\n")


if __name__ == "__main__":
    main()
