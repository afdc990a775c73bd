"""Engagement on real recordings: the service through its real path vs hri_engagement's rule.

    python -m benchmarks.engagement.recordings [--quick] [--rate R] [--format rmw_zenoh|bridge]

For each recording of the shared set (../shared/data/hri_engagement_bags and
hri_engagement_bags_2: hri_engagement's own test recordings, labelled ENGAGED or
DISENGAGED per person; ``scoring.labelled``):
- ours: the bag is replayed onto zenoh (``replay``, rmw_zenoh format by default) through a
  zenoh router to the real service (``--input ros2``, base frame camera_link, as
  hri_engagement's tests used); a consumer records the service's engagement events for
  ``person_<id>``;
- the rule's mode: the same real path with ``--engagement rule``;
- the rule: hri_engagement 2.0.1's "visual social engagement" and vote window, as the
  service's ``--engagement rule`` has them (``core.mutual_gaze``, ``core.rule``: mutual
  gaze x proxemics, field of view 60 deg, max distance 4 m, threshold 0.5, 10 s window at
  10 Hz, its vote thresholds), run as its node runs it (a 10 Hz timer over libhri's
  lookups), fed the same TF data (tf2's lookups through our TF buffer, tested against tf2
  itself).

Both are scored alike (``scoring``: level, ENGAGED-or-not, the two errors apart, final
level, first ENGAGED, changes a minute; means over person-recordings with 95 % bootstrap
intervals, with and without the ceiling row).
``--quick`` replays at 4x (CI); the full run replays at recorded speed. Then the same
recordings offline (``benchmarks.engagement.crossval``): the figures in-sample and cross-validated,
leaving one person out (and one recording out), per idea.
"""

from __future__ import annotations

import argparse
import json
import math
import threading
import time
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any, Literal

import zenoh

from facing_service.config.settings import Settings
from facing_service.contract import keys
from facing_service.contract.levels import Level
from facing_service.ros2.wire import RosFormat, Wire
from facing_service.shell.service import FacingService
from facing_service.testing import endpoint, free_port, loopback_config, wait_until
from facing_service.tools.replay import Replay

from .. import paths, results_file
from . import crossval, scoring
from .bags import read_bag
from .rule_path import rule_timelines
from .scoring import (
    BASE_FRAME,
    FOLDERS,
    ROW_HEAD,
    Row,
    Timeline,
    figures_line,
    row_cells,
    row_name,
    score,
    summaries,
    summary,
    timeline_of,
)

RESULTS = paths.RESULTS / "recordings.json"
#: The rule's figures on the first shared folder as measured outside the
#: project, which its re-implementation must reproduce there.
REFERENCE_FIGURES = {"level": 0.32, "engaged_or_not": 0.71, "final": 4, "first_engaged_s": 5.2}


def service_timelines(
    bag: Path,
    persons: list[str],
    rate: float,
    ros_format: RosFormat,
    engagement: Literal["service", "rule"] = "service",
) -> dict[str, Timeline]:
    """The real path: bag -> replay -> zenoh router -> service -> engagement events (the
    service's own machines, or ``engagement="rule"``: hri_engagement's as its mode)."""
    port = free_port()
    ep = endpoint(port)
    settings = Settings(
        mode="client",
        connect=[ep],
        no_multicast_scouting=True,
        cfg=["scouting/delay:0"],
        input="ros2",
        ros_format=ros_format.value,
        base_frame=BASE_FRAME,
        instance="evaluation",
        log_level="WARNING",
        engagement=engagement,
    )
    events: list[tuple[int, str, Level]] = []  # (stamp ns, body, level)
    lock = threading.Lock()

    def on_event(sample: zenoh.Sample) -> None:
        event = json.loads(sample.payload.to_bytes())
        stamp = event["stamp"]["sec"] * 1_000_000_000 + event["stamp"]["nanosec"]
        with lock:
            events.append((stamp, event["body_id"], Level[event["level"]]))

    client = loopback_config(connect=[ep], mode="client")
    with (
        zenoh.open(loopback_config(listen=[ep], mode="router")),
        FacingService(settings),
        zenoh.open(client) as consumer,
        zenoh.open(client) as robot,
    ):
        subscriber = consumer.declare_subscriber("hri/events/engagement/**", on_event)
        try:
            _wait_for_service(consumer)
            with Replay(robot, bag, Wire(ros_format)) as replay:
                replay.run(rate=rate)
                time.sleep(0.5)  # the last events on their way
        finally:
            subscriber.undeclare()
    messages = [t for _, t, _ in read_bag(bag)]
    start, end = messages[0], messages[-1]
    return {person: timeline_of(events, f"person_{person}", start, end) for person in persons}


def _wait_for_service(session: zenoh.Session, timeout: float = 10.0) -> None:
    token = keys.service_token("hri", "*")
    wait_until(
        lambda: any(r.ok for r in session.liveliness().get(token, timeout=0.5)),
        timeout,
        "the service's token",
    )


def evaluate(
    folders: Sequence[Path] = FOLDERS,
    rate: float = 1.0,
    ros_format: RosFormat = RosFormat.RMW_ZENOH,
    rule_mode: bool = True,
) -> dict[str, dict]:
    """Every labelled recording through the real path: the service, hri_engagement's rule,
    and (``rule_mode``) the service in the rule's mode, a second replay of each."""
    methods = ("service", "rule", "rule_mode") if rule_mode else ("service", "rule")
    rows: dict[str, list[Row]] = {method: [] for method in methods}
    for recording in scoring.labelled(folders):
        persons = list(recording.persons)
        timelines = {
            "service": service_timelines(recording.path, persons, rate, ros_format),
            "rule": rule_timelines(recording.path, persons),
        }
        if rule_mode:
            timelines["rule_mode"] = service_timelines(
                recording.path, persons, rate, ros_format, "rule"
            )
        for method, of_person in timelines.items():
            for person in persons:
                rows[method].append(
                    score(recording.name, person, recording.label, of_person[person])
                )
    return {
        method: {"summary": summaries(method_rows), "rows": [asdict(r) for r in method_rows]}
        for method, method_rows in rows.items()
    }


def first_folder_summary(results: dict[str, dict], method: str) -> dict[str, Any]:
    """A method's figures on the first shared folder alone (where the rule's reference
    figures were measured), ceiling included as they were."""
    first = {r.name for r in scoring.labelled(FOLDERS[:1])}
    rows = [Row(**r) for r in results[method]["rows"] if r["recording"] in first]
    return summary(rows, intervals=False)


def print_table(results: dict[str, dict]) -> None:
    print(f"{'':31} | {'service':^41} | {'rule':^41}")
    print(f"{'recording       person label':31} | {ROW_HEAD} | {ROW_HEAD}")
    for ours, theirs in zip(results["service"]["rows"], results["rule"]["rows"], strict=True):
        print(f"{row_name(ours):31} | {row_cells(ours)} | {row_cells(theirs)}")
    print("(* the ceiling row: left out of the targets)")
    for method in (m for m in ("service", "rule", "rule_mode") if m in results):
        for which, label in (("without_ceiling", "without *"), ("all", "all")):
            s = results[method]["summary"][which]
            print(f"{method:9} {label:9}  {figures_line(s)}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="replay at 4x (CI)")
    parser.add_argument("--rate", type=float, help="replay rate (default 1, or 4 with --quick)")
    parser.add_argument("--format", choices=[f.value for f in RosFormat], default="rmw_zenoh")
    parser.add_argument(
        "--bags", type=Path, nargs="+", default=list(FOLDERS), help="folders of labelled bags"
    )
    parser.add_argument(
        "--out",
        type=Path,
        help=f"write the results here (default: {RESULTS.name} for a full run at the recorded "
        "pace; a --quick or other-rate run writes nothing unless asked: the committed file "
        "is the full run's)",
    )
    args = parser.parse_args(argv)
    rate = args.rate or (4.0 if args.quick else 1.0)
    if not (math.isfinite(rate) and rate > 0):
        parser.error(f"--rate must be a positive number, got {rate}")
    for folder in args.bags:
        if not (folder / "labels.json").is_file():
            parser.error(f"--bags: {folder} has no labels.json (a folder of labelled bags)")
    out = args.out or (RESULTS if rate == 1.0 and tuple(args.bags) == FOLDERS else None)
    results = evaluate(args.bags, rate, RosFormat(args.format))
    print_table(results)
    judged = crossval.evaluate(args.bags)
    print("\nOffline, in-sample and cross-validated (python -m benchmarks.engagement.crossval):")
    crossval.print_results(judged)
    results["crossval"] = judged
    if out is None:
        print(f"(not written: {RESULTS} keeps the full run's figures; --out to write these)")
        return
    command = "python -m benchmarks.engagement.recordings"
    results_file.write(out, {"rate": rate, "format": args.format, **results}, command, vars(args))
    print(f"written to {out}")


if __name__ == "__main__":
    main()
