"""A session kept as MCAP (``record``, ``replay SESSION.mcap``): what recording costs the
service, and how a replay agrees with the run it recorded. Everything through a router,
as a robot's deployment is, on loopback.

    python -m benchmarks.session cost [--people 100] [--hz 30] [--seconds 20] [--repeat 2]
    python -m benchmarks.session agreement [--minutes 5] [--out FILE]

``cost``: the service's CPU (user + system, /proc) while a tracker streams, with and
without a ``record`` process beside it, alternated ``--repeat`` times (the machine is
shared and noisy: the ratio in the same run is the figure). ``agreement``: five simulated
people for ``--minutes`` into a service, recorded; played by ``replay`` into a fresh
service, recorded again; then poses, results, level changes and groups compared.
"""

from __future__ import annotations

import argparse
import json
import statistics
import tempfile
import time
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import zenoh

from facing_service.client.sim import Crowd, TrackerPublisher, simulate
from facing_service.testing import LOOPBACK_FLAGS, endpoint, free_port, loopback_config, running_cli
from facing_service.tools.session_record import SessionRecorder

from . import results_file
from .perf.driver import cpu_seconds


@contextmanager
def deployment() -> Iterator[tuple[str, int]]:
    """A router and a service (its client), on loopback: ``(endpoint, service pid)``."""
    router = endpoint(free_port())
    with running_cli("router", "-l", router, *LOOPBACK_FLAGS, capture=False):
        flags = ("-m", "client", "-e", router, "--log-level", "ERROR", *LOOPBACK_FLAGS)
        with running_cli("run", *flags, capture=False) as service:
            time.sleep(2.0)
            yield router, service.pid


def _stream(router: str, people: int, hz: float, seconds: float) -> TrackerPublisher:
    with zenoh.open(loopback_config(connect=[router], mode="client")) as tracker:
        publish = TrackerPublisher(tracker)
        crowd = Crowd(people=people, seed=1, start_s=time.time())
        simulate(publish, crowd, "base_link", "hri", hz, seconds)
        publish.close()
    return publish


def cost(people: int, hz: float, seconds: float, repeat: int) -> dict[str, Any]:
    """The service's CPU %: alone (nobody reads what it publishes, so zenoh sends nothing
    on), with a plain subscriber to the whole namespace (a robot app reading results: what
    a deployment has anyway), and with a recorder; alternated."""
    kinds = ("alone", "read", "recorded")
    runs: dict[str, list[float]] = {kind: [] for kind in kinds}
    with deployment() as (router, pid), tempfile.TemporaryDirectory() as scratch:
        for i in range(repeat):
            for kind in kinds:
                with _beside(kind, router, Path(scratch) / f"{kind}{i}.mcap"):
                    time.sleep(1.0)
                    before, started = cpu_seconds(pid), time.monotonic()
                    _stream(router, people, hz, seconds)
                    used = cpu_seconds(pid) - before
                    runs[kind].append(100.0 * used / (time.monotonic() - started))
                print(f"{kind:>9} run {i + 1}: the service at {runs[kind][-1]:.1f} % of a CPU")
    median = {kind: statistics.median(runs[kind]) for kind in kinds}
    return {"runs": runs, **{f"{k}_pct": round(v, 1) for k, v in median.items()},
            "recorded_over_read": round(median["recorded"] / median["read"], 3),
            "recorded_over_alone": round(median["recorded"] / median["alone"], 3)}  # fmt: skip


@contextmanager
def _beside(kind: str, router: str, out: Path) -> Iterator[None]:
    """Beside the service: nothing, a plain subscriber to the namespace, or a recorder."""
    if kind == "recorded":
        with running_cli("record", str(out), "-m", "client", "-e", router, *LOOPBACK_FLAGS,
                         capture=False):  # fmt: skip
            yield
    elif kind == "read":
        with zenoh.open(loopback_config(connect=[router], mode="client")) as reader:
            heard = reader.declare_subscriber("hri/**", lambda sample: None)
            yield
            heard.undeclare()
    else:
        yield


def _record(router: str, out: Path, feed: Any) -> None:
    """``feed()`` into the deployment at ``router`` while a recorder keeps it in ``out``."""
    with zenoh.open(loopback_config(connect=[router], mode="client")) as listener:
        recorder = SessionRecorder(listener, "hri", out)
        time.sleep(1.0)
        feed()
        time.sleep(2.0)  # the last answers
        recorder.close()


def _said(path: Path) -> dict[str, Any]:
    from mcap.reader import make_reader

    poses, facing, events, groups = [], set(), [], {}
    with path.open("rb") as stream:
        for schema, channel, message in make_reader(stream).iter_messages(log_time_order=True):
            m = json.loads(message.data)
            if schema is None:  # the recorder gives every channel its schema
                continue
            if schema.name == "pose":
                poses.append(message.data)
            elif schema.name == "facing_state":
                facing.add((channel.topic, m["stamp"]["sec"], m["stamp"]["nanosec"], m["facing"]))
            elif schema.name == "engagement_event":
                events.append((m["body_id"], m["stamp"]["sec"], m["stamp"]["nanosec"], m["level"]))
            elif schema.name == "frame_groups" and m.get("stamp"):
                stamp = (m["stamp"]["sec"], m["stamp"]["nanosec"])
                groups[stamp] = sorted(tuple(g["members"]) for g in m["groups"])
    return {"poses": poses, "facing": facing, "events": sorted(events), "groups": groups}


def agreement(minutes: float) -> dict[str, Any]:
    """A session recorded live, replayed into a fresh service and recorded again."""
    with tempfile.TemporaryDirectory() as scratch:
        first, second = Path(scratch) / "live.mcap", Path(scratch) / "replayed.mcap"
        sent: list[TrackerPublisher] = []
        with deployment() as (router, _):
            _record(router, first, lambda: sent.append(_stream(router, 5, 30.0, 60 * minutes)))
        with deployment() as (router, _):
            flags = ("--record", str(second), "-m", "client", "-e", router, *LOOPBACK_FLAGS)
            with running_cli("replay", str(first), *flags, capture=False) as proc:
                proc.wait(timeout=60 * minutes + 120)
        live, again = _said(first), _said(second)
    # Groups are worked out at --group-rate-hz on the service's clock, from the poses it
    # holds then: the replay's lists fall at other stamps. Each live list is compared
    # with the replay's list in force at its stamp (the last one at or before it).
    replayed = sorted(again["groups"])
    in_force = {
        stamp: again["groups"][max(r for r in replayed if r <= stamp)]
        for stamp in live["groups"]
        if replayed and replayed[0] <= stamp
    }
    same_groups = [s for s in in_force if in_force[s] == live["groups"][s]]
    return {
        "minutes": minutes,
        "poses_sent": sent[0].poses,
        "poses_recorded": len(live["poses"]),
        "poses_replayed_equal": again["poses"] == live["poses"],
        "results": len(live["facing"]),
        "results_equal": len(live["facing"] & again["facing"]),
        "results_only_replayed": len(again["facing"] - live["facing"]),
        "level_changes": len(live["events"]),
        "level_changes_in_both": sum((Counter(live["events"]) & Counter(again["events"])).values()),
        "group_lists": len(live["groups"]),
        "group_lists_compared": len(in_force),
        "group_lists_equal": len(same_groups),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    which = parser.add_subparsers(dest="which", required=True)
    c = which.add_parser("cost")
    c.add_argument("--people", type=int, default=100)
    c.add_argument("--hz", type=float, default=30.0)
    c.add_argument("--seconds", type=float, default=20.0)
    c.add_argument("--repeat", type=int, default=2)
    a = which.add_parser("agreement")
    a.add_argument("--minutes", type=float, default=5.0)
    for sub in (c, a):
        sub.add_argument("--out", type=Path, help="write the figures (JSON)")
    args = parser.parse_args(argv)
    if args.which == "cost":
        figures = cost(args.people, args.hz, args.seconds, args.repeat)
    else:
        figures = agreement(args.minutes)
    print(json.dumps(figures, indent=1))
    if args.out is not None:
        results_file.write(args.out, figures, f"python -m benchmarks.session {args.which}",
                           vars(args))  # fmt: skip


if __name__ == "__main__":
    main()
