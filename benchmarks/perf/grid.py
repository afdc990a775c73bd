"""The grid: what a target costs depends on how the tracker connects (peer,
client), how it publishes (``Session.put``, declared publishers) and who consumes
(nobody, the per-body results, everything under the namespace). Every cell measures each
bare relay and the service, one after the other, each fed by one ``Driver`` whose
session is the tracker and the consumer (as the outside scripts in ../shared/bench do):
latency (one pose in flight), a soak, a BLOCK flood, and the same soak after it. Each
service figure is a ratio to the cheapest relay *for that cell* (by the first soak's
CPU), measured in the same run.
"""

from __future__ import annotations

import argparse
import subprocess
import time
from contextlib import AbstractContextManager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import zenoh

from facing_service.contract import keys
from facing_service.testing import (
    LOOPBACK_FLAGS,
    endpoint,
    free_port,
    loopback_config,
    running_cli,
    wait_until,
)

from .driver import CONSUMERS, STYLES, Driver

MODES = ("peer", "client")
#: The bare relays (``benchmarks.perf.relay --style``): Session.put on string keys, a
#: publisher declared per output key, and both keys declared (the cheapest nearly always).
RELAYS = ("relay_put", "relay_publishers", "relay_keys")
TARGETS = (*RELAYS, "service")


@dataclass(frozen=True)
class Sizes:
    warmup: int
    latency_n: int
    burst_n: int
    bodies: int
    hz: float
    soak_s: float

    @classmethod
    def of(cls, args: argparse.Namespace) -> Sizes:
        return cls(args.warmup, args.latency_n, args.burst_n, args.soak_bodies, args.soak_hz,
                   args.soak_s)  # fmt: skip


def cells(chosen: str | None) -> list[tuple[str, str, str]]:
    """Every cell, or those named ``mode/style/consumer`` (comma-separated)."""
    every = [(m, s, c) for m in MODES for s in STYLES for c in CONSUMERS]
    if chosen is None:
        return every
    wanted = [tuple(cell.split("/")) for cell in chosen.split(",")]
    unknown = [cell for cell in wanted if cell not in every]
    if unknown:
        raise SystemExit(f"--cells: no such cell {'/'.join(unknown[0])} (mode/style/consumer)")
    return wanted  # type: ignore[return-value]


def start(
    kind: str, port: int, before: Path | None = None
) -> AbstractContextManager[subprocess.Popen[str]]:
    """A target as its own process: the service through its CLI, as users run it (the
    one of the source tree ``before`` for ``service-before``), or a bare relay."""
    if kind.startswith("service"):
        ros = ("--input", "ros2", "--base-frame", "base_link") if kind == "service-ros" else ()
        tree = {"PYTHONPATH": str(before)} if kind == "service-before" and before else None
        return running_cli(
            "run",
            "-l",
            endpoint(port),
            *LOOPBACK_FLAGS,
            "--log-level",
            "WARNING",
            *ros,
            env=tree,
            capture=False,
        )
    style = kind.removeprefix("relay_")
    return running_cli(
        "-l", endpoint(port), "--style", style, module="benchmarks.perf.relay", capture=False
    )


def wait_ready(session: zenoh.Session, timeout: float = 20.0) -> None:
    selector = keys.status_key("hri", keys.ALL_FRAMES)
    wait_until(lambda: any(r.ok for r in session.get(selector, timeout=0.5)), timeout, "the target")


def cell_of(measured: dict[str, Any]) -> tuple[str, str, str]:
    return measured["mode"], measured["style"], measured["consumer"]


def open_tracker(port: int, mode: str) -> zenoh.Session:
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


def measure(
    target: str, cell: tuple[str, str, str], sizes: Sizes, before: Path | None = None
) -> dict[str, Any]:
    """One target in one cell: latency (when someone consumes), soak, flood, soak."""
    mode, style, consumer = cell
    port = free_port()
    with start(target, port, before) as proc, open_tracker(port, mode) as session:
        driver = Driver(session, ros=target == "service-ros", style=style, consumer=consumer)
        try:
            wait_ready(session)
            driver.announce(sizes.bodies)  # the ROS 2 path: who is tracked
            driver.soak(proc.pid, sizes.bodies, sizes.hz, 0.5, first_sec=1)  # keys known
            result: dict[str, Any] = {}
            if driver.consumes:
                driver.latency(sizes.warmup, first_sec=1_000)
                result["latency"] = driver.latency(sizes.latency_n, first_sec=1_000_000)
            result["soak"] = driver.soak(
                proc.pid, sizes.bodies, sizes.hz, sizes.soak_s, first_sec=2_000_000
            )
            result["burst"] = driver.burst(
                sizes.burst_n, sizes.bodies, first_sec=3_000_000, pid=proc.pid
            )
            result["soak_after"] = driver.soak(
                proc.pid, sizes.bodies, sizes.hz, sizes.soak_s, first_sec=4_000_000
            )
        finally:
            driver.close()
    return result


def run(
    chosen: list[tuple[str, str, str]], sizes: Sizes, before: Path | None = None
) -> list[dict[str, Any]]:
    """Every chosen cell; with ``before`` (a source tree), that tree's service too, in
    the same run, right after the relays and before this one's."""
    targets = (*RELAYS, "service-before", "service") if before else TARGETS
    out = []
    for cell in chosen:
        figures = {target: measure(target, cell, sizes, before) for target in targets}
        cheapest = min(RELAYS, key=lambda t: figures[t]["soak"]["cpu_percent"])
        out.append(
            {
                "mode": cell[0],
                "style": cell[1],
                "consumer": cell[2],
                "targets": figures,
                "cheapest_relay": cheapest,
                "ratios": ratios(figures[cheapest], figures["service"]),
            }
        )
        if before:
            out[-1]["ratios_before"] = ratios(figures[cheapest], figures["service-before"])
        print(line(out[-1]), flush=True)
    return out


def ratios(relay: dict[str, Any], service: dict[str, Any]) -> dict[str, float | None]:
    """The service over the relay; None where nothing could be measured (no consumer,
    or a soak below the clock's tick at --quick sizes)."""

    def r(a: float | None, b: float | None) -> float | None:
        return None if a is None or not b else a / b

    consumed = "latency" in service
    return {
        "soak_cpu": r(service["soak"]["cpu_percent"], relay["soak"]["cpu_percent"]),
        "soak_cpu_after_flood": r(
            service["soak_after"]["cpu_percent"], relay["soak_after"]["cpu_percent"]
        ),
        "latency_p50": r(service["latency"]["p50_ms"], relay["latency"]["p50_ms"])
        if consumed
        else None,
        "burst_throughput": r(service["burst"]["results_per_s"], relay["burst"]["results_per_s"]),
    }


def line(cell: dict[str, Any]) -> str:
    t = cell["targets"]
    us = "  ".join(f"{name.removeprefix('relay_')} {t[name]['soak']['us_per_pose']:5.1f}"
                   for name in t)  # fmt: skip
    said = " | ".join(
        f"{which}: " + "  ".join(f"{k} {'-' if v is None else f'{v:.2f}'}" for k, v in r.items())
        for which in ("ratios_before", "ratios")
        if (r := cell.get(which)) is not None
    )
    return f"{cell['mode']:6} {cell['style']:10} {cell['consumer']:10} us/pose: {us} | {said}"
