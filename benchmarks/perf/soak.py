"""Floods against the real service process, with its resident memory.

    python -m benchmarks.perf.soak [--ids 200000] [--max-bodies 10000] [--garbage 100000]

1. a flood of unique body ids, far beyond --max-bodies: memory must level off once the
   bound is reached (the service refuses new bodies with reason 'capacity');
2. a flood of garbage payloads: memory stays flat, every sample counted.
Prints the service's RSS at each stage. Takes a minute or two at the defaults.
"""

from __future__ import annotations

import argparse
import random
import time

import zenoh

from facing_service.contract import keys

from .common import (
    free_port,
    loopback_config,
    pose_payload,
    rss_mb,
    running_service,
    send,
    status,
    wait_for_status,
)


def wait_until_handled(session: zenoh.Session, total: int, timeout: float = 300.0) -> float:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        s = status(session)
        if s is not None and s.counters["samples_accepted"] + sum(s.rejected.values()) >= total:
            return time.monotonic()
        time.sleep(0.2)
    raise SystemExit(f"the service did not handle {total} samples within {timeout} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ids", type=int, default=200_000)
    parser.add_argument("--max-bodies", type=int, default=10_000)
    parser.add_argument("--garbage", type=int, default=100_000)
    args = parser.parse_args()

    port = free_port()
    flags = ("--max-bodies", str(args.max_bodies), "--stale-after-s", "3600")
    with (
        running_service(port, *flags) as proc,
        zenoh.open(loopback_config(connect=[f"tcp/127.0.0.1:{port}"])) as tracker,
    ):
        wait_for_status(tracker)
        rows = [("started", 0, rss_mb(proc.pid))]
        sent = 0
        started = time.monotonic()
        for i in range(args.ids):
            send(
                tracker,
                keys.pose_key("hri", body_id=f"id{i}", frame_id="map"),
                pose_payload(f"id{i}", "map", 2.0, 0.0, 180.0, 1),
            )
            sent += 1
            if sent == args.max_bodies or sent % (args.ids // 4) == 0:
                wait_until_handled(tracker, sent)
                rows.append((f"{sent} unique ids", sent, rss_mb(proc.pid)))
        wait_until_handled(tracker, sent)
        ids_s = time.monotonic() - started
        rows.append((f"{sent} unique ids", sent, rss_mb(proc.pid)))

        rng = random.Random(7)
        started = time.monotonic()
        for i in range(args.garbage):
            send(
                tracker,
                keys.pose_key("hri", body_id=f"g{i % 50}", frame_id="map"),
                rng.randbytes(rng.randrange(1, 300)),
            )
        sent += args.garbage
        wait_until_handled(tracker, sent)
        garbage_s = time.monotonic() - started
        rows.append((f"+ {args.garbage} garbage", sent, rss_mb(proc.pid)))
        final = status(tracker)

    print(f"{'stage':<28}{'samples':>10}{'RSS MB':>10}")
    for stage, n, rss in rows:
        print(f"{stage:<28}{n:>10}{rss:>10.1f}")
    assert final is not None
    print(
        f"tracked {final.bodies_tracked_total} (bound {args.max_bodies}); rejected "
        f"capacity={final.rejected['capacity']} malformed_json={final.rejected['malformed_json']}"
        f"; unique-id flood {args.ids / ids_s:.0f}/s, garbage {args.garbage / garbage_s:.0f}/s"
    )


if __name__ == "__main__":
    main()
