"""A robot over a link that stalls and is cut, as a judge plays it: the service
and a consumer in processes of their own, the robot's session through a userspace TCP
proxy in this one (``lossy_link.JitterProxy``: a delay of 0-60 ms, stall, resume, reset),
three people at 30 Hz.

``play`` runs the whole scenario and returns what the consumer saw and the service said:
two ENGAGED people through a stall and a cut, one person who really leaves while the
others go on, then the tracker that dies (no backlog ever). Timings are measured, never
asserted here: the test asserts what must hold, and prints the figures.
"""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from typing import IO, Any

import zenoh

from facing_service.testing import LOOPBACK_FLAGS, endpoint, free_port, loopback_config
from facing_service.tools.loopback import wait_for_port

from lossy_link import JitterProxy
from poses import pose_json

#: The consumer, a FacingClient beside the service: every 0.1 s a line of what it holds,
#: and a line for each body lost.
CONSUMER = """
import json, sys, time
from facing_service import FacingClient
with FacingClient(frame="base_link", connect=[sys.argv[1]], no_multicast_scouting=True) as c:
    c.on_lost(lambda body: print(json.dumps({"t": time.time(), "lost": body.body_id}),
                                 flush=True))
    while True:
        states = c.bodies()
        newest = max((s.stamp.sec + s.stamp.nanosec * 1e-9 for s in states.values()), default=0)
        levels = {b: str(level) for b, level in c.engagement().items()}
        print(json.dumps({"t": time.time(), "newest": newest, "levels": levels}), flush=True)
        time.sleep(0.1)
"""

#: Where each person stands, and whether they face the robot.
PEOPLE = {"ann": (1.5, 0.5, 0.0), "bob": (1.5, -0.5, 0.0), "cat": (2.5, 0.0, 90.0)}


@dataclass
class Heard:
    """What the consumer printed, as it came."""

    lines: list[dict[str, Any]] = field(default_factory=list)
    lock: threading.Lock = field(default_factory=threading.Lock)

    def read(self, stream: IO[str]) -> None:
        for line in stream:
            with self.lock:
                self.lines.append(json.loads(line))

    def since(self, t: float) -> list[dict[str, Any]]:
        with self.lock:
            return [line for line in self.lines if line["t"] >= t]

    def wait(self, holds: Any, timeout: float, what: str) -> dict[str, Any]:
        deadline = time.time() + timeout
        while time.time() < deadline:
            with self.lock:
                found = next((line for line in reversed(self.lines) if holds(line)), None)
            if found is not None:
                return found
            time.sleep(0.05)
        raise TimeoutError(f"{what}: not within {timeout:g} s")


class Robot:
    """A tracker publishing ``PEOPLE`` at 30 Hz, stamped with the wall clock, until told
    to drop one or to die."""

    def __init__(self, connect: str) -> None:
        config = loopback_config(connect=[connect])
        retry = {"period_init_ms": 250, "period_max_ms": 500, "period_increase_factor": 2}
        config.insert_json5("connect/retry", json.dumps(retry))
        self.session = zenoh.open(config)
        self.people = dict(PEOPLE)
        self.dead = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        block = zenoh.CongestionControl.BLOCK
        while not self.dead.wait(1 / 30):
            sec, nanosec = divmod(round(time.time() * 1e9), 1_000_000_000)
            for who, (x, y, off) in list(self.people.items()):
                payload = pose_json(who, "base_link", x=x, y=y, off_deg=off, sec=sec,
                                    nanosec=nanosec)  # fmt: skip
                try:
                    self.session.put(f"hri/bodies/{who}/pose/base_link", payload,
                                     congestion_control=block)  # fmt: skip
                except zenoh.ZError:
                    return

    def close(self) -> None:
        self.dead.set()
        self._thread.join(timeout=5)
        self.session.close()


@dataclass
class Report:
    """What a judge reads off the run."""

    lost_in_stall: list[str]
    drops_in_stall: list[str]  # ENGAGED people said lower during or after the stall
    fresh_after_stall_s: float
    left_lost_after_s: float
    lost_in_cut: list[str]
    drops_in_cut: list[str]
    fresh_after_cut_s: float
    dead_cleared_after_s: float
    log: list[str]
    service_alive: bool


def _drops(lines: list[dict[str, Any]], who: tuple[str, ...]) -> list[str]:
    return sorted({b for line in lines for b in who if line.get("levels", {}).get(b, "ENGAGED")
                   != "ENGAGED"})  # fmt: skip


def _fresh(heard: Heard, since: float) -> float:
    """Seconds from ``since`` to the first line whose newest stamp is from after it."""
    line = heard.wait(lambda line: line.get("newest", 0) >= since, 15, "fresh results")
    return line["t"] - since


def play(stall_s: float = 4.0, hold_s: float = 6.0) -> Report:
    """The scenario, start to end (about 35 s)."""
    port = free_port()
    service = subprocess.Popen(
        [sys.executable, "-m", "facing_service", "run", "-l", endpoint(port), *LOOPBACK_FLAGS,
         "--base-frame", "base_link", "--hold-silent-s", str(hold_s), "--log-level", "INFO"],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
    )  # fmt: skip
    log: list[str] = []
    threading.Thread(target=lambda: log.extend(service.stdout or ()), daemon=True).start()
    consumer = subprocess.Popen([sys.executable, "-c", CONSUMER, endpoint(port)],
                                stdout=subprocess.PIPE, text=True)  # fmt: skip
    heard = Heard()
    threading.Thread(target=heard.read, args=(consumer.stdout,), daemon=True).start()
    wait_for_port(port, timeout=30)
    proxy = JitterProxy(port, "127.0.0.1", jitter_s=0.06)  # a Wi-Fi link's 0-60 ms
    robot = Robot(endpoint(proxy.port))
    engaged = ("ann", "bob")
    try:
        heard.wait(lambda line: all(line.get("levels", {}).get(b) == "ENGAGED" for b in engaged),
                   30, "ann and bob ENGAGED")  # fmt: skip
        stalled = time.time()
        proxy.cut()
        time.sleep(stall_s)
        resumed = time.time()
        proxy.resume()
        fresh_stall = _fresh(heard, resumed)
        time.sleep(1.0)
        during = heard.since(stalled)
        left = time.time()
        del robot.people["cat"]  # cat walks away; the others go on
        lost = heard.wait(lambda line: line.get("lost") == "cat", 15, "cat lost")
        cut = time.time()
        proxy.reset(refuse_s=2.0)
        fresh_cut = _fresh(heard, cut + 2.0)
        time.sleep(1.0)
        in_cut = heard.since(cut)
        robot.dead.set()  # the tracker dies: no backlog ever comes
        died = time.time()
        cleared = heard.wait(lambda line: line.get("lost") in engaged, hold_s + 15, "cleared")
        alive = service.poll() is None
    finally:
        robot.close()
        proxy.close()
        consumer.kill()
        consumer.wait(timeout=10)
        service.terminate()
        service.wait(timeout=10)
    return Report(
        lost_in_stall=[line["lost"] for line in during if "lost" in line],
        drops_in_stall=_drops(during, engaged),
        fresh_after_stall_s=round(fresh_stall, 2),
        left_lost_after_s=round(lost["t"] - left, 2),
        lost_in_cut=[line["lost"] for line in in_cut if "lost" in line],
        drops_in_cut=_drops(in_cut, engaged),
        fresh_after_cut_s=round(fresh_cut, 2),
        dead_cleared_after_s=round(cleared["t"] - died, 2),
        log=[line.rstrip() for line in log],
        service_alive=alive,
    )


if __name__ == "__main__":  # the figures of one run, for a closing note
    report = play(float(sys.argv[1]) if len(sys.argv) > 1 else 4.0)
    print(json.dumps({k: v for k, v in vars(report).items() if k != "log"}, indent=1))
    print("\n".join(line for line in report.log if "input" in line))
