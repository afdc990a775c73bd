"""Engagement on real recordings: the service through its real path vs hri_engagement's rule.

    python -m benchmarks.recordings [--quick] [--rate R] [--format rmw_zenoh|bridge]

For each recording of ../shared/data/hri_engagement_bags (hri_engagement's own test
recordings, labelled ENGAGED or DISENGAGED per person):
- ours: the bag is replayed onto zenoh (``replay``, rmw_zenoh format by default) through a
  zenoh router to the real service (``--input ros2``, base frame camera_link, as
  hri_engagement's tests used); a consumer records the service's engagement events for
  ``person_<id>``;
- the rule: a faithful re-implementation of hri_engagement's "visual social engagement"
  (engagement.visual_social_engagement + VoteWindow: mutual gaze x proxemics, field of view
  60 deg, max distance 4 m, threshold 0.5, 10 s window at 10 Hz, its vote thresholds), fed
  the same TF data (tf2's lookups through our TF buffer, tested against tf2 itself).

Both levels are sampled every 0.1 s of recording time. Per person-recording: the share of
samples after a 2 s warm-up where the level equals the label, and where "ENGAGED or not"
matches, the final level, the time to the first ENGAGED, the number of level changes.
Summaries are means over person-recordings (how the rule's reference figures were made).
``--quick`` replays at 4x (CI); the full run replays at recorded speed. Then the same
recordings offline (``benchmarks.crossval``): the figures in-sample and cross-validated,
leaving one recording out in turn, per family of candidate settings.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import threading
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import zenoh

from facing_service.config.settings import Settings
from facing_service.contract import keys
from facing_service.core.engagement import Level, VoteWindow, visual_social_engagement
from facing_service.core.tf_errors import TfError
from facing_service.ros2 import types as ros2_types
from facing_service.ros2.input import tf_inputs
from facing_service.ros2.people import People
from facing_service.ros2.wire import RosFormat, Wire
from facing_service.shell.service import FacingService
from facing_service.testing import endpoint, free_port, loopback_config, wait_until
from facing_service.tools.replay import Replay

BAGS = Path(__file__).resolve().parents[2] / "shared" / "data" / "hri_engagement_bags"
RESULTS = Path(__file__).resolve().parent / "results" / "recordings.json"
BASE_FRAME = "camera_link"  # hri_engagement's tests' reference frame
TICK_NS = 100_000_000  # hri_engagement's rate: 10 Hz
WARM_UP_S = 2.0
#: The rule's figures as measured outside the project (the issue), which ours must beat.
REFERENCE_FIGURES = {"level": 0.32, "engaged_or_not": 0.71, "final": 4, "first_engaged_s": 5.2}

Timeline = list[tuple[float, Level]]  # (seconds since the recording's start, level)


@dataclass
class Row:
    recording: str
    person: str
    label: str
    level: float  # share of samples after the warm-up with level == label
    engaged_or_not: float
    final_ok: bool
    first_engaged_s: float | None
    changes: int


def ticks(start_ns: int, end_ns: int) -> list[int]:
    return list(range(start_ns + TICK_NS, end_ns + 1, TICK_NS))


def rule_timelines(bag: Path, persons: list[str]) -> dict[str, Timeline]:
    """hri_engagement's rule on the recording's TF data: every 0.1 s, each tracked person
    with a face votes from their gaze frame looked up in the base frame (time 0, as libhri
    does); no vote when the lookup fails."""
    messages = list(ros2_types.read_bag(bag))
    start, end = messages[0][1], messages[-1][1]
    people = People(BASE_FRAME)
    windows: dict[str, VoteWindow] = {}
    faces: dict[str, str] = {}
    tracked: list[str] = []
    timelines: dict[str, Timeline] = {p: [] for p in persons}
    i = 0
    for tick in ticks(start, end):
        while i < len(messages) and messages[i][1] <= tick:
            topic, _, message = messages[i]
            i += 1
            if topic in ("/tf", "/tf_static"):
                people.on_tf(tf_inputs(message), static=topic == "/tf_static")
            elif topic == "/humans/persons/tracked":
                tracked = list(message.ids)
            elif topic.endswith("/face_id"):
                faces[topic.split("/")[3]] = message.data
        for person in tracked:
            window = windows.setdefault(person, VoteWindow())
            vote = None
            if face := faces.get(person):
                try:
                    gaze, _ = people.tf.lookup(BASE_FRAME, f"gaze_{face}", 0)
                except TfError:
                    pass
                else:
                    score = visual_social_engagement(gaze.translation, gaze.rotation)
                    vote = score is not None and score > 0.5
            window.vote(vote)
        for person, timeline in timelines.items():
            level = windows[person].level if person in windows else Level.UNKNOWN
            timeline.append(((tick - start) / 1e9, level))
    return timelines


def service_timelines(
    bag: Path, persons: list[str], rate: float, ros_format: RosFormat
) -> dict[str, Timeline]:
    """The real path: bag -> replay -> zenoh router -> service -> engagement events."""
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
    messages = [t for _, t, _ in ros2_types.read_bag(bag)]
    start, end = messages[0], messages[-1]
    return {person: timeline_of(events, f"person_{person}", start, end) for person in persons}


def timeline_of(
    events: list[tuple[int, str, Level]], body: str, start_ns: int, end_ns: int
) -> Timeline:
    """A body's level at every tick, from its engagement events (stamp ns, body, level)."""
    mine = sorted((s, level) for s, who, level in events if who == body)
    timeline, j, level = [], 0, Level.UNKNOWN
    for tick in ticks(start_ns, end_ns):
        while j < len(mine) and mine[j][0] <= tick:
            level = mine[j][1]
            j += 1
        timeline.append(((tick - start_ns) / 1e9, level))
    return timeline


def _wait_for_service(session: zenoh.Session, timeout: float = 10.0) -> None:
    token = keys.service_token("hri", "*")
    wait_until(
        lambda: any(r.ok for r in session.liveliness().get(token, timeout=0.5)),
        timeout,
        "the service's token",
    )


def score(recording: str, person: str, label: Level, timeline: Timeline) -> Row:
    after = [level for t, level in timeline if t >= WARM_UP_S]
    engaged = label is Level.ENGAGED
    first = next((t for t, level in timeline if level is Level.ENGAGED), None)
    previous, changes = Level.UNKNOWN, 0
    for _, level in timeline:
        changes += level is not previous
        previous = level
    return Row(
        recording,
        person,
        label.name,
        sum(level is label for level in after) / len(after),
        sum((level is Level.ENGAGED) == engaged for level in after) / len(after),
        timeline[-1][1] is label,
        None if first is None else round(first, 1),
        changes,
    )


def summary(rows: list[Row]) -> dict[str, float | int | None]:
    engaged = [r for r in rows if r.label == "ENGAGED"]
    firsts = [math.inf if r.first_engaged_s is None else r.first_engaged_s for r in engaged]
    median = statistics.median(firsts) if firsts else None
    return {
        "level": round(statistics.mean(r.level for r in rows), 3),
        "engaged_or_not": round(statistics.mean(r.engaged_or_not for r in rows), 3),
        "final": sum(r.final_ok for r in rows),
        "of": len(rows),
        "first_engaged_s": None if median is None or math.isinf(median) else round(median, 2),
        "changes": sum(r.changes for r in rows),
    }


def evaluate(
    bags: Path = BAGS, rate: float = 1.0, ros_format: RosFormat = RosFormat.RMW_ZENOH
) -> dict[str, dict]:
    labels = json.loads((bags / "labels.json").read_text())["recordings"]
    rows: dict[str, list[Row]] = {"service": [], "rule": []}
    for recording in sorted(labels):
        persons = labels[recording]["persons"]
        label = Level(labels[recording]["expected_level"])
        ours = service_timelines(bags / recording, persons, rate, ros_format)
        rule = rule_timelines(bags / recording, persons)
        for person in persons:
            rows["service"].append(score(recording, person, label, ours[person]))
            rows["rule"].append(score(recording, person, label, rule[person]))
    return {
        method: {"summary": summary(method_rows), "rows": [asdict(r) for r in method_rows]}
        for method, method_rows in rows.items()
    }


def print_table(results: dict[str, dict]) -> None:
    print(f"{'recording':16} {'person':6} {'label':10} | {'service':^32} | {'rule':^32}")
    head = f"{'level':>6} {'eng?':>5} {'final':>5} {'1st ENG':>7} {'chg':>4}"
    print(f"{'':35}| {head} | {head}")
    for ours, rule in zip(results["service"]["rows"], results["rule"]["rows"], strict=True):
        cells = [
            f"{r['level']:6.0%} {r['engaged_or_not']:5.0%} {'ok' if r['final_ok'] else 'x':>5} "
            f"{'never' if r['first_engaged_s'] is None else r['first_engaged_s']:>7} "
            f"{r['changes']:4}"
            for r in (ours, rule)
        ]
        who = f"{ours['recording']:16} {ours['person']:6} {ours['label']:10}"
        print(f"{who} | {cells[0]} | {cells[1]}")
    for method in ("service", "rule"):
        s = results[method]["summary"]
        print(
            f"{method:8} level {s['level']:.0%}, ENGAGED or not {s['engaged_or_not']:.0%}, "
            f"final {s['final']}/{s['of']}, first ENGAGED (median) {s['first_engaged_s']} s, "
            f"{s['changes']} level changes"
        )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="replay at 4x (CI)")
    parser.add_argument("--rate", type=float, help="replay rate (default 1, or 4 with --quick)")
    parser.add_argument("--format", choices=[f.value for f in RosFormat], default="rmw_zenoh")
    parser.add_argument("--bags", type=Path, default=BAGS)
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
    out = args.out or (RESULTS if rate == 1.0 and args.bags == BAGS else None)
    results = evaluate(args.bags, rate, RosFormat(args.format))
    print_table(results)
    from . import crossval  # (it builds on this module)

    judged = crossval.evaluate(args.bags)
    print("\nOffline, in-sample and cross-validated (python -m benchmarks.crossval):")
    crossval.print_results(judged)
    results["crossval"] = judged
    if out is None:
        print(f"(not written: {RESULTS} keeps the full run's figures; --out to write these)")
        return
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"rate": rate, "format": args.format, **results}, indent=2) + "\n")
    print(f"written to {out}")


if __name__ == "__main__":
    main()
