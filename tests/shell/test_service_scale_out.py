"""Scale-out with zenoh's own routing: several service instances behind one router,
sharded by namespace (one per robot), seen by a consumer through single wildcard queries."""

from __future__ import annotations

import signal
import threading
import time
from contextlib import ExitStack

import pytest
import zenoh

from facing_service.testing import running_cli

from loopback import endpoint, get, send, wait_until_answered
from poses import pose_json

pytestmark = pytest.mark.slow  # processes, recordings or seconds-long scenarios

ROBOTS = ("robot1", "robot2", "robot3")


def test_three_shards_behind_one_router(net):
    router = net.router()
    ep = endpoint(router.port)
    with ExitStack() as stack:
        services = {
            robot: stack.enter_context(
                running_cli(
                    "run",
                    "-m",
                    "client",
                    "-e",
                    ep,
                    "--namespace",
                    f"{robot}/hri",
                    "--instance",
                    robot,
                    "--base-frame",
                    "base_link",
                )
            )
            for robot in ROBOTS
        }
        tracker = net.client(ep, mode="client")
        consumer = net.client(ep, mode="client")
        for robot in ROBOTS:
            wait_until_answered(consumer, f"{robot}/hri/facing/base_link", timeout=20)

        # each robot's tracker feeds its own shard: robotN sees N people, the first facing
        for n, robot in enumerate(ROBOTS, start=1):
            for i in range(n):
                body = f"{robot}-p{i}"
                off = 0.0 if i == 0 else 90.0
                send(
                    tracker,
                    f"{robot}/hri/bodies/{body}/pose/base_link",
                    pose_json(body, "base_link", off_deg=off),
                )
        deadline = time.monotonic() + 10
        while True:
            frames = dict(get(consumer, "*/hri/facing/**"))  # one query, every shard
            if all(
                len(f["bodies_tracked"]) == n
                for n, f in enumerate(
                    (
                        frames.get(f"{r}/hri/facing/base_link", {"bodies_tracked": []})
                        for r in ROBOTS
                    ),
                    start=1,
                )
            ):
                break
            assert time.monotonic() < deadline, frames
            time.sleep(0.05)
        assert set(frames) == {f"{r}/hri/facing/base_link" for r in ROBOTS}
        assert {k: v["bodies_facing"] for k, v in frames.items()} == {
            f"{r}/hri/facing/base_link": [f"{r}-p0"] for r in ROBOTS
        }
        per_body = dict(get(consumer, "*/hri/bodies/*/facing/base_link"))
        assert len(per_body) == 1 + 2 + 3
        statuses = dict(get(consumer, "*/hri/services/facing/*/status"))
        assert {s["instance"] for s in statuses.values()} == set(ROBOTS)

        # a crash of one instance removes its token; the others keep serving
        gone = threading.Event()
        watcher = consumer.liveliness().declare_subscriber(
            "*/hri/services/facing/*",
            lambda s: (
                gone.set()
                if s.kind == zenoh.SampleKind.DELETE and str(s.key_expr).startswith("robot2/")
                else None
            ),
        )
        try:
            services["robot2"].send_signal(signal.SIGKILL)
            services["robot2"].wait(timeout=10)
            assert gone.wait(10), "robot2's liveliness token outlived it"
        finally:
            watcher.undeclare()
        tokens = {str(r.ok.key_expr) for r in consumer.liveliness().get("*/hri/services/facing/*")}
        assert tokens == {"robot1/hri/services/facing/robot1", "robot3/hri/services/facing/robot3"}
        frames = dict(get(consumer, "*/hri/facing/**"))
        assert set(frames) == {"robot1/hri/facing/base_link", "robot3/hri/facing/base_link"}
        send(tracker, "robot3/hri/bodies/new/pose/base_link", pose_json("new", "base_link"))
        deadline = time.monotonic() + 10
        while "new" not in get(consumer, "robot3/hri/facing/base_link")[0][1]["bodies_tracked"]:
            assert time.monotonic() < deadline
            time.sleep(0.05)
