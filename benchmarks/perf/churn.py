"""An hour of people: arrivals and departures, router restarts, a consumer coming and going.

    python -m benchmarks.perf.churn [--minutes 60] [--people 20] [--hz 10] [--restart-every-s 300]

The real service runs in client mode on a router (``facing-service router``, its own
process); a tracker and a consumer reach it through that router, as on a robot. People
arrive (a new id each), stay 10-90 s and leave, half with a DELETE and half by falling
silent (the service's staleness). Every ``--restart-every-s`` the router is killed
(SIGKILL, a crash) and started again 3 s later on the same port. A consumer subscribes for
30 s of every minute. Every 10 s the service's resident memory, threads and open file
descriptors are read from /proc.

Says: the curves (``--out`` JSON, ``--figure`` SVG), their drift after the first five
minutes, poses sent and accepted outside the outages (nothing may be lost there), each
outage's loss and return as the service logged them, and results out of order at the
consumer. A benchmark, not a test: it takes ``--minutes``.
"""

from __future__ import annotations

import argparse
import json
import random
import re
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import zenoh

from facing_service.config.session import zenoh_config
from facing_service.config.settings import Settings
from facing_service.contract import keys
from facing_service.contract.poses import pose_dict, yaw_rotation
from facing_service.contract.stamps import ZERO, Time
from facing_service.testing import LOOPBACK_FLAGS, endpoint, running_cli, wait_for_port

from .. import results_file
from .common import free_port, proc_status, rss_mb, status, wait_for_status
from .figures import line_panels

#: The router is down this long at each restart; poses sent from the kill until this long
#: after the return (the issue's bound for results to flow again) may be lost.
DOWN_S = 3.0
SETTLE_S = 1.5
SAMPLE_EVERY_S = 10.0
WARM_UP_S = 300.0
WINDOW_S = 600.0


def proc_counts(pid: int) -> tuple[float, int, int]:
    """Resident MB, threads, open descriptors of a process (Linux /proc)."""
    status = proc_status(pid)
    fds = len(list(Path(f"/proc/{pid}/fd").iterdir()))
    return rss_mb(pid, status), int(status["Threads"]), fds


class RouterProcess:
    """``facing-service router`` on a fixed port; ``kill()`` is SIGKILL (a crash)."""

    def __init__(self, port: int) -> None:
        self.port = port
        self.proc: subprocess.Popen[bytes] | None = None

    def start(self) -> None:
        self.proc = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "facing_service",
                "router",
                "-l",
                endpoint(self.port),
                *LOOPBACK_FLAGS,
                "--log-level",
                "ERROR",
            ],
        )
        wait_for_port(self.port, timeout=20.0)

    def kill(self) -> None:
        if self.proc is not None:
            self.proc.send_signal(signal.SIGKILL)
            self.proc.wait()
            self.proc = None


@dataclass
class Visitor:
    body: str
    leaves_at: float
    x: float
    y: float
    yaw: float
    delete: bool


@dataclass
class Consumer:
    """Subscribes for part of every minute; counts results and any that go back in time."""

    port: int
    session: zenoh.Session | None = None
    subscriber: zenoh.Subscriber[None] | None = None
    received: int = 0
    out_of_order: int = 0
    joins: int = 0
    last: dict[str, Time] = field(default_factory=dict)

    def on_result(self, sample: zenoh.Sample) -> None:
        if sample.kind != zenoh.SampleKind.PUT:
            return
        value = json.loads(sample.payload.to_bytes())
        stamp = Time.of(value["stamp"]["sec"], value["stamp"]["nanosec"])
        body = str(sample.key_expr)
        if stamp < self.last.get(body, ZERO):
            self.out_of_order += 1
        self.last[body] = stamp
        self.received += 1

    def join(self) -> None:
        try:
            self.session = zenoh.open(robot_side(self.port))
        except zenoh.ZError:  # the router just back, not listening yet: the next tick
            return
        self.subscriber = self.session.declare_subscriber(
            keys.facing_key("hri", body_id="*", frame_id="map"), self.on_result
        )
        self.joins += 1

    def leave(self) -> None:
        if self.subscriber is not None and self.session is not None:
            self.subscriber.undeclare()
            self.session.close()
        self.subscriber = self.session = None


def robot_side(port: int) -> zenoh.Config:
    """A tracker's or consumer's session on the router, reconnecting as the service's own
    default (--reconnect-s) does: with zenoh's default backoff (up to 4 s) they, not the
    service, would decide how long results stop."""
    return zenoh_config(
        Settings(
            mode="client",
            connect=[endpoint(port)],
            no_multicast_scouting=True,
            cfg=["scouting/delay:0"],
        )
    )


def outages_said(log_text: str) -> tuple[int, int, list[float]]:
    """Loss lines, return lines, and each return's stated outage length."""
    lost = len(re.findall(r"lost every router and peer", log_text))
    back = [float(s) for s in re.findall(r"back in touch with \S+ after ([0-9.]+) s", log_text)]
    return lost, len(back), back


class Churn:
    """One hour of a robot's life, a tick at a time: the router killed and back, a
    consumer joining and leaving, people arriving and leaving, their poses sent, the
    service's process sampled."""

    def __init__(self, args: argparse.Namespace, router: RouterProcess, tracker: zenoh.Session,
                 consumer: Consumer, service_pid: int, start: float) -> None:  # fmt: skip
        self.args, self.router, self.tracker = args, router, tracker
        self.consumer, self.service_pid, self.start = consumer, service_pid, start
        self.rng = random.Random(11)
        self.samples: list[dict[str, float]] = []
        self.restarts: list[float] = []
        self.outages: list[tuple[float, float]] = []  # (kill, return + SETTLE_S), from start
        self.sent_total = self.sent_outside = 0
        self.people: list[Visitor] = []
        self.next_id = 0
        self.next_sample = start
        self.next_restart = start + args.restart_every_s
        self.down_until: float | None = None

    def tick(self, now: float, period: float) -> None:
        self.router_turn(now)
        minute_s = (now - self.start) % 60
        if self.consumer.session is None and minute_s < 30 and self.down_until is None:
            self.consumer.join()  # (a client with no router fails at once: not while down)
        elif self.consumer.session is not None and minute_s >= 30:
            self.consumer.leave()
        self.arrivals(now, period)
        self.send(now)
        if now >= self.next_sample:
            self.sample(now)

    def router_turn(self, now: float) -> None:
        """Killed every ``--restart-every-s``, back ``DOWN_S`` later."""
        if self.down_until is None and now >= self.next_restart:
            self.router.kill()
            self.restarts.append(now - self.start)
            self.down_until = now + DOWN_S
        elif self.down_until is not None and now >= self.down_until:
            self.router.start()  # back once it listens: its start-up is part of the outage
            self.outages.append((self.restarts[-1], time.monotonic() - self.start + SETTLE_S))
            self.down_until = None
            self.next_restart = now + self.args.restart_every_s

    def arrivals(self, now: float, period: float) -> None:
        """Poisson arrivals keeping about --people present; each stays 10-90 s."""
        rng = self.rng
        if rng.random() < self.args.people / 50.0 * period:
            self.people.append(
                Visitor(f"p{self.next_id}", now + rng.uniform(10, 90), rng.uniform(1, 6),
                        rng.uniform(-3, 3), rng.uniform(-180, 180), rng.random() < 0.5)
            )  # fmt: skip
            self.next_id += 1

    def send(self, now: float) -> None:
        """Everyone present's pose; those whose time is up leave (half DELETEd)."""
        wall = time.time_ns()
        since = now - self.start
        in_outage = self.down_until is not None or any(a <= since <= b for a, b in self.outages)
        for person in list(self.people):
            key = keys.pose_key("hri", body_id=person.body, frame_id="map")
            if now >= person.leaves_at:
                self.people.remove(person)
                if person.delete:
                    self.tracker.delete(key)
                continue
            person.yaw += self.rng.uniform(-5, 5)
            payload = pose_dict(
                person.body, "map", Time(wall), (person.x, person.y, 0.0), yaw_rotation(person.yaw)
            )
            self.tracker.put(
                key, json.dumps(payload).encode(), congestion_control=zenoh.CongestionControl.BLOCK
            )
            self.sent_total += 1
            self.sent_outside += not in_outage

    def sample(self, now: float) -> None:
        rss, threads, fds = proc_counts(self.service_pid)
        self.samples.append({"t_min": (now - self.start) / 60, "rss_mb": rss, "threads": threads,
                             "fds": fds, "present": len(self.people)})  # fmt: skip
        self.next_sample += SAMPLE_EVERY_S
        print(
            f"{self.samples[-1]['t_min']:6.1f} min  RSS {rss:6.1f} MB  threads {threads:3d}"
            f"  fds {fds:3d}  present {len(self.people):3d}  ids {self.next_id}",
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=60.0)
    parser.add_argument("--people", type=int, default=20, help="present at once, on average")
    parser.add_argument("--hz", type=float, default=10.0)
    parser.add_argument("--restart-every-s", type=float, default=300.0)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/churn.json"))
    parser.add_argument("--figure", type=Path, default=Path("docs/figures/churn.svg"))
    args = parser.parse_args()

    port = free_port()
    router = RouterProcess(port)
    router.start()
    flags = ("-m", "client", "-e", endpoint(port), *LOOPBACK_FLAGS,
             "--base-frame", "map", "--log-level", "INFO")  # fmt: skip
    consumer = Consumer(port)
    with (
        tempfile.NamedTemporaryFile("w+", suffix=".log", prefix="churn-") as log_file,
        running_cli("run", *flags, capture=False, stdout=log_file) as service,
        zenoh.open(robot_side(port)) as tracker,
    ):
        wait_for_status(tracker, timeout=30)
        start = time.monotonic()
        churn = Churn(args, router, tracker, consumer, service.pid, start)
        period = 1.0 / args.hz
        tick = start
        while (now := time.monotonic()) < start + args.minutes * 60:
            churn.tick(now, period)
            tick += period
            time.sleep(max(0.0, tick - time.monotonic()))
        if churn.down_until is not None:
            router.start()
        consumer.leave()
        time.sleep(2.0)
        final = status(tracker, timeout=5.0)
        log_file.seek(0)
        said = outages_said(log_file.read())
    router.kill()
    assert final is not None, "the service stopped answering its status query"
    report(args, churn, final.counters, said)


def drift(samples: list[dict[str, float]], name: str) -> dict[str, float]:
    """Flat or not: the mean of the first WINDOW_S after the warm-up against the mean of
    the last WINDOW_S (a single sample may fall in an outage, when zenoh's link threads
    and sockets are down and back), and the extremes after the warm-up."""
    after = [s for s in samples if s["t_min"] * 60 >= WARM_UP_S] or samples
    start, end = after[0]["t_min"] * 60, after[-1]["t_min"] * 60
    first = [s[name] for s in after if s["t_min"] * 60 < start + WINDOW_S]
    last = [s[name] for s in after if s["t_min"] * 60 > end - WINDOW_S]
    first_mean, last_mean = sum(first) / len(first), sum(last) / len(last)
    values = [s[name] for s in after]
    return {
        "first_window_mean": first_mean,
        "last_window_mean": last_mean,
        "last_over_first": last_mean / first_mean,
        "min": min(values),
        "max": max(values),
    }


def report(
    args: argparse.Namespace,
    churn: Churn,
    counters: dict[str, int],
    said: tuple[int, int, list[float]],
) -> None:
    lost_said, back_said, back_lengths = said
    samples, restarts, consumer, ids = churn.samples, churn.restarts, churn.consumer, churn.next_id
    sent_total, sent_outside = churn.sent_total, churn.sent_outside
    result = {
        "minutes": args.minutes,
        "people": args.people,
        "hz": args.hz,
        "restart_every_s": args.restart_every_s,
        "router_down_s": DOWN_S,
        "unique_ids": ids,
        "restarts": len(restarts),
        "outages_said": {"lost": lost_said, "back": back_said, "lengths_s": back_lengths},
        "sent": sent_total,
        "sent_outside_outages": sent_outside,
        "accepted": counters["samples_accepted"],
        "counters": counters,
        "consumer": {
            "joins": consumer.joins,
            "results": consumer.received,
            "out_of_order": consumer.out_of_order,
        },
        "drift": {name: drift(samples, name) for name in ("rss_mb", "threads", "fds")},
        "samples": samples,
    }
    results_file.write(args.out, result, "python -m benchmarks.perf.churn", vars(args), indent=1)
    figure(args.figure, samples, restarts)
    said_back = ", ".join(f"{s:.1f}" for s in back_lengths)
    for name, d in result["drift"].items():
        print(
            f"{name:8} first 10 min after the warm-up {d['first_window_mean']:.1f}, last 10 "
            f"min {d['last_window_mean']:.1f} (x{d['last_over_first']:.3f}); range "
            f"{d['min']:.0f}-{d['max']:.0f}"
        )
    print(
        f"router restarts {len(restarts)}; the service said: lost {lost_said}, back {back_said}"
        f" (lengths {said_back} s)"
    )
    print(
        f"poses sent {sent_total}, outside outages {sent_outside}, accepted "
        f"{counters['samples_accepted']}; consumer joined {consumer.joins} times, got "
        f"{consumer.received} results, {consumer.out_of_order} out of order; {ids} people"
    )
    print(f"wrote {args.out} and {args.figure}")


def figure(path: Path, samples: list[dict[str, float]], restarts: list[float]) -> None:
    """The hour as an SVG: memory, threads, descriptors and people, restarts dashed."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(
        line_panels(
            [s["t_min"] for s in samples],
            [
                ("resident memory, MB", [s["rss_mb"] for s in samples]),
                ("threads", [s["threads"] for s in samples]),
                ("open file descriptors", [s["fds"] for s in samples]),
                ("people present", [s["present"] for s in samples]),
            ],
            marks=[t / 60 for t in restarts],
            x_label="minutes (dashed: router killed, back 3 s later)",
        )
    )


if __name__ == "__main__":
    main()
