"""One benchmark run: the bare relays and the real service, fed by the same driver.

    python -m benchmarks                  # full sizes (about 9 minutes)
    python -m benchmarks --quick          # seconds; what CI runs so this never rots

For each tracker style (a ``Session.put`` per sample, or declared publishers), both bare
relays (``Session.put``, declared publishers) and the service; then the ROS 2 path, fed
as a robot feeds it. Prints tables in which every service figure is also a ratio to the
cheapest relay (by soak CPU) for the same tracker style, measured in the same run (this
machine is shared and noisy: ratios, not absolute numbers, are the comparison), and
writes benchmarks/results/latest.json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from contextlib import AbstractContextManager
from importlib import metadata
from pathlib import Path

import zenoh

from facing_service import __version__
from facing_service.contract import keys
from facing_service.testing import (
    LOOPBACK_FLAGS,
    endpoint,
    free_port,
    loopback_config,
    running_cli,
    wait_until,
)

from . import core
from .driver import STYLES, Driver
from .report import CORE_SPEEDUP_MIN, PAGE, TARGETS, render, verdicts

RESULTS = Path(__file__).resolve().parent / "results" / "latest.json"


#: The bare relays, by how they publish (``benchmarks.relay --style``).
RELAYS = ("relay_put", "relay_publishers")


def start(kind: str, port: int) -> AbstractContextManager[subprocess.Popen[str]]:
    if kind.startswith("service"):  # through its CLI, as users run it
        ros = ("--input", "ros2", "--base-frame", "base_link") if kind == "service-ros" else ()
        if kind == "service-declared":  # per-body results through declared publishers
            ros = ("--result-publishers", "declared")
        return running_cli(
            "run",
            "-l",
            endpoint(port),
            *LOOPBACK_FLAGS,
            "--log-level",
            "WARNING",
            *ros,
            capture=False,
        )
    style = kind.removeprefix("relay_")
    return running_cli(
        "-l", endpoint(port), "--style", style, module="benchmarks.relay", capture=False
    )


def wait_ready(session: zenoh.Session, timeout: float = 20.0) -> None:
    selector = keys.status_key("hri", keys.ALL_FRAMES)
    wait_until(lambda: any(r.ok for r in session.get(selector, timeout=0.5)), timeout, "the target")


def measure(kind: str, args: argparse.Namespace, style: str = "put") -> dict:
    port = free_port()
    with (
        start(kind, port) as proc,
        zenoh.open(loopback_config(connect=[endpoint(port)])) as session,
    ):
        driver = Driver(session, ros=kind == "service-ros", style=style)
        try:
            wait_ready(session)
            driver.announce(max(args.burst_bodies, args.soak_bodies, 1))
            driver.latency(args.warmup, first_sec=1)  # warm-up: imports, caches, links
            result = {"latency": driver.latency(args.latency_n, first_sec=1_000_000)}
            result["burst"] = driver.burst(args.burst_n, args.burst_bodies, first_sec=2_000_000)
            result["soak"] = driver.soak(
                proc.pid, args.soak_bodies, args.soak_hz, args.soak_s, first_sec=3_000_000
            )
        finally:
            driver.close()
    return result


def cheapest_relay(runs: dict) -> str:
    """The relay that spent the least CPU in the soak, for one tracker style."""
    return min(RELAYS, key=lambda name: runs[name]["soak"]["cpu_percent"])


def ratios(relay: dict, service: dict) -> dict[str, float]:
    def r(section: str, key: str) -> float:
        return service[section][key] / relay[section][key]

    return {
        "latency_p50": r("latency", "p50_ms"),
        "latency_p90": r("latency", "p90_ms"),
        "latency_p99": r("latency", "p99_ms"),
        "burst_throughput": r("burst", "results_per_s"),
        "soak_cpu": r("soak", "cpu_percent"),
        "soak_p99": r("soak", "p99_ms"),
    }


def ros_ratios(json_path: dict, ros_path: dict) -> dict[str, float]:
    """The ROS 2 path against the JSON path of the same service: CPU per pose in the soak
    (both at the same rate), burst throughput and soak latency."""

    def per_pose(run: dict) -> float:
        return run["soak"]["cpu_percent"] / max(run["soak"]["received"], 1)

    return {
        "ros_cpu_per_pose": per_pose(ros_path) / per_pose(json_path),
        "ros_burst_throughput": ros_path["burst"]["results_per_s"]
        / json_path["burst"]["results_per_s"],
        "ros_soak_p99": ros_path["soak"]["p99_ms"] / json_path["soak"]["p99_ms"],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="tiny sizes, for CI")
    parser.add_argument("--warmup", type=int, default=200)
    parser.add_argument("--latency-n", type=int, default=2000)
    parser.add_argument("--burst-n", type=int, default=100_000)
    parser.add_argument("--burst-bodies", type=int, default=100)
    parser.add_argument("--soak-bodies", type=int, default=100)
    parser.add_argument("--soak-hz", type=float, default=30.0)
    parser.add_argument("--soak-s", type=float, default=60.0)
    parser.add_argument("--core-sizes", default="1,100,10000,1000000")
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args()
    if args.quick:
        args.warmup, args.latency_n, args.burst_n, args.soak_s = 20, 50, 2000, 2.0
        args.core_sizes = "1,100,10000"

    sizes = tuple(int(n) for n in args.core_sizes.split(","))
    report: dict = {
        "version": __version__,
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
            "zenoh": metadata.version("eclipse-zenoh"),
        },
        "parameters": {k: v for k, v in vars(args).items() if k != "out"} | {"out": str(args.out)},
        "styles": {
            style: {kind: measure(kind, args, style) for kind in (*RELAYS, "service")}
            for style in STYLES
        },
        "service_ros": measure("service-ros", args),
        "core": core.measure(sizes, min_time=0.05 if args.quick else 0.3),
    }
    for runs in report["styles"].values():
        runs["cheapest"] = cheapest_relay(runs)
        runs["ratios"] = ratios(runs[runs["cheapest"]], runs["service"])
    report["ros_ratios"] = ros_ratios(
        report["styles"]["publishers"]["service"], report["service_ros"]
    )
    report["verdicts"] = verdicts(report)
    report["targets"] = TARGETS
    report["core_speedup_min"] = CORE_SPEEDUP_MIN
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2) + "\n")
    print(render(report))
    print(f"\nwritten to {args.out}; python -m benchmarks.report puts it in {PAGE.name}")


if __name__ == "__main__":
    sys.exit(main())
