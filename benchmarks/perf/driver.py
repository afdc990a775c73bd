"""Drives a target (a bare relay or the service) through zenoh and measures it.

What a target costs depends on how the tracker and the consumers connect (docs/
performance.md, the grid), so the driver is one tracker session of either mode (the
caller opens it), with either publishing style (``STYLES``): ``put``, a ``Session.put``
per sample (what a script does), or ``publishers``, a declared publisher per key (how
rmw_zenoh and most trackers publish: the ROS 2 mode always does, with its attachments);
and on the same session a consumer (``CONSUMERS``) of nothing, of the per-body results,
or of everything under the namespace.

The same code drives every target, from the same process, so the figures compare like
with like:
- latency: one pose in flight at a time, pose -> per-body result;
- burst: N poses over M bodies as fast as BLOCK puts go; results/s and loss;
- soak: M bodies at a fixed rate (a tracker) for S seconds; the target's CPU % (whole
  and per thread group), p99 latency and resident memory at start and end.
Without a consumer nothing comes back: the soak measures CPU only, and a burst is a
flood whose end is when the target's CPU goes quiet.
"""

from __future__ import annotations

import json
import os
import re
import statistics
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import zenoh

from facing_service.contract import keys
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.wire import GID_SIZE, Wire, attachment

from .common import ids_payload, pose_payload, rss_mb, tf_payload

_STAMP = re.compile(rb'"sec":\s*(\d+)')
_TICKS = os.sysconf("SC_CLK_TCK")


def _cpu_of(stat: Path) -> float:
    """User + system CPU seconds in a /proc stat file (a process's or a thread's)."""
    fields = stat.read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / _TICKS


def cpu_seconds(pid: int) -> float:
    """User + system CPU time a process has used so far (Linux /proc)."""
    return _cpu_of(Path(f"/proc/{pid}/stat"))


def thread_cpu_seconds(pid: int) -> dict[int, tuple[str, float]]:
    """Each live thread of a process: its OS name and the CPU seconds it has used."""
    threads = {}
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            threads[int(task.name)] = ((task / "comm").read_text().strip(), _cpu_of(task / "stat"))
        except OSError:  # the thread ended meanwhile
            continue
    return threads


def thread_group(name: str) -> str:
    """Who a thread works for, from its OS name: the service names its own
    (``facing-worker``, ``facing-publish``, ``facing-alarm``); zenoh's runtime names its
    (``rx-0``, ``tx-0``, ``net-0``, ``acc-0``, ``app-0``); the rest are Python's (the
    main thread, zenoh's Python callback threads)."""
    if name.startswith("facing-"):
        return name
    role = name.split("-", 1)[0]
    if role in ("rx", "tx"):
        return f"zenoh {role}"
    if role in ("net", "acc", "app"):
        return "zenoh other"
    return "python, other"


def cpu_by_thread(
    before: dict[int, tuple[str, float]], after: dict[int, tuple[str, float]], wall_s: float
) -> dict[str, float]:
    """CPU % of one core per thread group between two readings (threads that ended in
    between are not counted: the soak's threads live throughout)."""
    groups: dict[str, float] = {}
    for tid, (name, cpu) in after.items():
        spent = cpu - before.get(tid, (name, 0.0))[1]
        group = thread_group(name)
        groups[group] = groups.get(group, 0.0) + 100 * spent / wall_s
    return dict(sorted(groups.items()))


@dataclass
class _Results:
    """What arrives on the output keys: counts, and arrival times by (body, stamp)."""

    lock: threading.Lock = field(default_factory=threading.Lock)
    count: int = 0
    last: float = 0.0
    arrivals: dict[tuple[str, int], float] = field(default_factory=dict)
    event: threading.Event = field(default_factory=threading.Event)
    keep_times: bool = False
    body_prefix: str = ""  # ROS 2 mode: results are keyed body_<id>

    def on_sample(self, sample: zenoh.Sample) -> None:
        now = time.perf_counter()
        parts = str(sample.key_expr).rsplit("/", 4)  # NS/bodies/<id>/facing/<frame>
        if (
            sample.kind != zenoh.SampleKind.PUT
            or len(parts) != 5
            or parts[1::2] != ["bodies", "facing"]
        ):
            return  # a consumer of everything also gets poses, frames, engagement...
        with self.lock:
            self.count += 1
            self.last = now
            if self.keep_times:
                body = str(sample.key_expr).split("/")[-3].removeprefix(self.body_prefix)
                match = _STAMP.search(sample.payload.to_bytes())
                if match:
                    self.arrivals[(body, int(match.group(1)))] = now
        self.event.set()


def percentiles(values_s: list[float]) -> dict[str, float]:
    ms = np.array(values_s) * 1000
    return {f"p{p}_ms": float(np.percentile(ms, p)) for p in (50, 90, 99)}


#: How a tracker publishes: a Session.put per sample, or a declared publisher per key.
STYLES = ("put", "publishers")
#: Who consumes, on the tracker's session: nobody, the per-body results, everything.
CONSUMERS = ("none", "results", "everything")


class Driver:
    """One zenoh session that feeds a target and records its results: JSON poses, or
    (with ``ros``) the same poses as a ROS 2 robot sends them, one-body TFMessages on
    rmw_zenoh keys with their attachment, through a declared publisher."""

    def __init__(
        self,
        session: zenoh.Session,
        namespace: str = "hri",
        ros: bool = False,
        style: str = "put",
        consumer: str = "results",
    ) -> None:
        self.session = session
        self.ns = namespace
        self.ros = ros
        self.style = "publishers" if ros else style
        self._publishers: dict[str, zenoh.Publisher] = {}
        self._wire = Wire()
        self._gid = os.urandom(GID_SIZE)
        self._sequence_number = 0
        self.results = _Results(body_prefix="body_" if ros else "")
        self.consumes = consumer != "none"
        wanted = {
            "none": None,
            "results": keys.facing_key(namespace, body_id="*", frame_id="*"),
            "everything": f"{namespace}/**",
        }[consumer]
        self._subscriber = None
        if wanted is not None:
            self._subscriber = session.declare_subscriber(wanted, self.results.on_sample)
        self._payloads: dict[tuple[int, int, int], bytes] = {}

    def close(self) -> None:
        for publisher in self._publishers.values():
            publisher.undeclare()
        if self._subscriber is not None:
            self._subscriber.undeclare()

    def announce(self, bodies: int) -> None:
        """ROS 2 mode: the tracker's list of who exists (/humans/bodies/tracked)."""
        if self.ros:
            key = self._wire.key("/humans/bodies/tracked", ros2_types.IDS_LIST)
            self._send(key, ids_payload([f"b{i}" for i in range(bodies)]))

    def _put(self, body: int, sec: int, off_deg: float) -> None:
        x, y = 1.0 + body % 7, (body % 5) - 2.0
        yaw = float(np.degrees(np.arctan2(-y, -x)) + off_deg)
        if self.ros:
            key = self._wire.key("/tf", ros2_types.TF_MESSAGE)
            self._send(key, tf_payload(f"b{body}", "base_link", x, y, yaw, sec))
        else:
            key = keys.pose_key(self.ns, body_id=f"b{body}", frame_id="base_link")
            self._send(key, pose_payload(f"b{body}", "base_link", x, y, yaw, sec))

    def _send(self, key: str, payload: bytes) -> None:
        extra = None
        if self.ros:
            self._sequence_number += 1
            extra = attachment(self._sequence_number, time.time_ns(), self._gid)
        if self.style == "put":
            self.session.put(
                key, payload, attachment=extra, congestion_control=zenoh.CongestionControl.BLOCK
            )
            return
        publisher = self._publishers.get(key)
        if publisher is None:
            publisher = self._publishers[key] = self.session.declare_publisher(
                key, congestion_control=zenoh.CongestionControl.BLOCK
            )
        publisher.put(payload, attachment=extra)

    def reset(self, keep_times: bool = False) -> None:
        with self.results.lock:
            self.results.count = 0
            self.results.arrivals.clear()
            self.results.keep_times = keep_times
        self.results.event.clear()

    def latency(self, n: int, first_sec: int) -> dict[str, float]:
        """n round trips, one pose in flight at a time."""
        self.reset()
        rtts = []
        for i in range(n):
            self.results.event.clear()
            started = time.perf_counter()
            self._put(0, first_sec + i, off_deg=(i % 40) - 20.0)
            if not self.results.event.wait(5):
                raise RuntimeError(f"no result for pose {i} within 5 s")
            rtts.append(time.perf_counter() - started)
        return {**percentiles(rtts), "n": n}

    def burst(
        self, n: int, bodies: int, first_sec: int, pid: int, quiet_s: float = 2.0
    ) -> dict[str, float | None]:
        """n poses over ``bodies`` bodies as fast as possible; results/s and loss. With no
        consumer it is a flood whose results nobody sees: it ends when the target's CPU
        goes quiet (``_quiet``), and only the sending rate is known."""
        self.reset()
        started = time.perf_counter()
        for i in range(n):
            self._put(i % bodies, first_sec + i // bodies, off_deg=(i % 50) - 25.0)
        sent_s = time.perf_counter() - started
        if not self.consumes:
            return {"sent": n, "received": None, "lost": None, "sent_per_s": n / sent_s,
                    "results_per_s": None, "drained_s": _quiet(pid) - started,
                    **self.service_counters()}  # fmt: skip
        while True:  # until everything arrived, or nothing more for quiet_s
            seen = self.results.count
            if seen >= n:
                break
            time.sleep(0.05)
            if self.results.count == seen and time.perf_counter() - self.results.last > quiet_s:
                break
        received = self.results.count
        elapsed = max(self.results.last - started, 1e-9)
        return {
            "sent": n,
            "received": received,
            "lost": n - received,
            "sent_per_s": n / sent_s,
            "results_per_s": received / elapsed,
            **self.service_counters(),
        }

    def service_counters(self) -> dict[str, int]:
        """The service's own view of a run (where a loss happened); empty for the relay."""
        for reply in self.session.get(keys.status_key(self.ns, "*"), timeout=2):
            if reply.ok is not None:
                counters = json.loads(reply.ok.payload.to_bytes()).get("counters")
                if counters is None:  # the relay's readiness answer: no counters
                    continue
                wanted = ("samples_accepted", "results_published", "results_superseded")
                return {f"service_{k}": counters[k] for k in wanted}
        return {}

    def soak(self, pid: int, bodies: int, hz: float, seconds: float, first_sec: int) -> dict:
        """A tracker's load: every 1/hz s, one pose per body. CPU, p99 latency, memory."""
        self.reset(keep_times=True)
        sent: dict[tuple[str, int], float] = {}
        rss_start, cpu_start, threads_start = rss_mb(pid), cpu_seconds(pid), thread_cpu_seconds(pid)
        started = time.perf_counter()
        frame = 0
        while (now := time.perf_counter()) - started < seconds:
            for body in range(bodies):
                sec = first_sec + frame
                sent[(f"b{body}", sec)] = time.perf_counter()
                self._put(body, sec, off_deg=((frame + body) % 60) - 30.0)
            frame += 1
            next_frame = started + frame / hz
            if next_frame > now:
                time.sleep(
                    next_frame - time.perf_counter() if next_frame > time.perf_counter() else 0
                )
        wall = time.perf_counter() - started
        time.sleep(1.0)  # let the last results arrive
        cpu, threads = cpu_seconds(pid) - cpu_start, thread_cpu_seconds(pid)
        with self.results.lock:
            arrivals = dict(self.results.arrivals)
        latencies = [arrivals[k] - t for k, t in sent.items() if k in arrivals]
        seen = self.consumes  # without a consumer: CPU and memory only
        return {
            "bodies": bodies,
            "hz": hz,
            "seconds": round(wall, 2),
            "sent": len(sent),
            "received": len(latencies) if seen else None,
            "cpu_percent": 100 * cpu / wall,
            "us_per_pose": cpu / len(sent) * 1e6,
            "cpu_by_thread": cpu_by_thread(threads_start, threads, wall),
            "rss_start_mb": rss_start,
            "rss_end_mb": rss_mb(pid),
            "p99_ms": percentiles(latencies)["p99_ms"] if latencies else None,
            "p50_ms": statistics.median(latencies) * 1000 if latencies else None,
        }


def _quiet(pid: int, window_s: float = 0.5, most: float = 0.04, limit_s: float = 30.0) -> float:
    """When process ``pid`` spends less than ``most`` of a core over ``window_s`` (it
    has worked through what it was sent), or after ``limit_s``: perf_counter time."""
    deadline = time.perf_counter() + limit_s
    while time.perf_counter() < deadline:
        before = cpu_seconds(pid)
        time.sleep(window_s)
        if cpu_seconds(pid) - before < most * window_s:
            return time.perf_counter() - window_s
    return time.perf_counter()
