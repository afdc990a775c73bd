"""Engagement levels, side by side: our smoothed-score state machine vs the reference
vote-window rule of ROS4HRI's hri_engagement (facing_service.core.rule: the service's
``--engagement rule``; here each simulated body votes whether it faces the robot, within
the tutorial's 20 deg), on the same noisy tracks.

    python -m benchmarks.engagement.simulated [--people 20] [--seed 0] [--quick]

Each simulated person follows a script (``labelled.labelled_track``): walks up from the side,
faces the robot 10 s, turns away, glances back for 0.6 s, walks past, stands with their
back turned, faces the robot again, leaves; 5 deg yaw noise, 10 % of frames dropped plus
0.5 s dropout bursts, 30 Hz. Both methods see the same samples through the same geometry
(detector.classify_one). Reported per method:
- time from "starts facing" (ground truth) to ENGAGED, median over episodes;
- time from "turns away" to DISENGAGED, median;
- spurious level changes per person-minute: changes against the ground truth (to ENGAGED
  while the person is not engaging, to DISENGAGING/DISENGAGED while they are); walking up
  and leaving carry no ground truth (someone walking at the robot may well engage).
"""

from __future__ import annotations

import argparse
import math
import random
import statistics
from pathlib import Path

from facing_service.config.profiles import engagement_params
from facing_service.config.settings import Settings
from facing_service.core import rule
from facing_service.core.detector import classify_one
from facing_service.core.engagement import (
    Engagement,
    EngagementParams,
    Level,
    advance,
    facing_score,
    step,
)

from .. import paths, results_file
from .labelled import LabelledSample, Segment, labelled_track

RESULTS = paths.RESULTS / "engagement.json"
TARGETS = {"to_engaged_s": 1.0, "to_disengaged_s": 1.5, "spurious_per_person_minute": 0.1}
TICK_S = 0.1  # the reference votes at 10 Hz; ours is also advanced at that rate
RULE = rule.RuleParams()  # hri_engagement's window: 10 Hz, 10 s


def script(rng: random.Random) -> list[Segment]:
    """One person's visit, with positions varied per person."""
    # Walks are lateral (across the robot's view, not toward it): someone walking at the
    # robot *is* facing it, which would contradict the "not engaging" label.
    x = rng.uniform(1.2, 2.2)
    sign = rng.choice([-1, 1])
    spot = (x, sign * rng.uniform(0.0, 0.8))
    side = (x, sign * rng.uniform(3.5, 4.5))
    back = (x, -sign * rng.uniform(1.5, 2.0))
    far = (x, -sign * rng.uniform(5.0, 6.0))
    return [
        Segment(4.0, side, spot, "path", facing=None),  # walks up: may engage, or not
        Segment(10.0, spot, spot, "robot", facing=True),  # faces the robot
        Segment(8.0, spot, spot, "away", facing=False),  # turns away
        Segment(0.6, spot, spot, "robot", facing=False),  # a glance: not engaging
        Segment(6.0, spot, spot, "away", facing=False),
        Segment(5.0, spot, back, "path", facing=False),  # walks past
        Segment(10.0, back, back, "away", facing=False),  # back turned
        Segment(8.0, back, back, "robot", facing=True),  # faces the robot again
        Segment(5.0, back, far, "path", facing=None),  # leaves
    ]


def decide(sample: LabelledSample) -> tuple[float | None, float | None, bool]:
    half = math.radians(sample.yaw_deg) / 2
    _, angle, distance, facing = classify_one(
        (sample.x, sample.y, 0.0), (0.0, 0.0, math.sin(half), math.cos(half)), 20.0
    )
    return angle, distance, facing


def levels(track: list[LabelledSample], method: str, p: EngagementParams) -> list[tuple]:
    """The level changes ``(t, level)`` a method produces on a track."""
    changes: list[tuple[float, Level]] = []
    ours, reference = Engagement(), rule.Votes()
    level = Level.UNKNOWN
    i, t, end = 0, 0.0, track[-1].t
    latest: LabelledSample | None = None
    while t <= end:
        t += TICK_S
        fresh = None
        while i < len(track) and track[i].t <= t:
            fresh = latest = track[i]
            if method == "ours":
                angle, distance, _ = decide(latest)
                ours = step(ours, latest.t, facing_score(angle, distance, p), p)
            i += 1
        if method == "ours":
            ours = advance(ours, t, p)
            new = ours.level
        elif fresh is not None:  # the reference only votes when it has a new observation
            reference = rule.tick(reference, 1 if decide(fresh)[2] else -1, RULE)
            new = reference.level
        else:
            new = level
        if new is not level:
            changes.append((t, new))
            level = new
        del latest
        latest = None
    return changes


def truth_at(track: list[LabelledSample], t: float) -> bool | None:
    previous = track[0].facing
    for sample in track:
        if sample.t > t:
            break
        previous = sample.facing
    return previous


def episodes(segments: list[Segment]) -> tuple[list[float], list[float]]:
    """Onsets and offsets of the long 'facing' stretches (>= 5 s), in track time."""
    onsets, offsets, t = [], [], 0.0
    for segment in segments:
        if segment.facing and segment.seconds >= 5.0:
            onsets.append(t)
            offsets.append(t + segment.seconds)
        t += segment.seconds
    return onsets, offsets


def first(changes: list[tuple], after: float, level: Level, before: float) -> float | None:
    for t, new in changes:
        if after <= t < before and new is level:
            return t - after
    return None


def evaluate(people: int, seed: int, p: EngagementParams) -> dict:
    rng = random.Random(seed)
    report: dict[str, dict] = {}
    scenes = []
    for person in range(people):
        segments = script(rng)
        scenes.append((segments, labelled_track(segments, seed=seed * 1000 + person)))
    for method in ("ours", "reference"):
        to_engaged, to_disengaged, spurious, minutes, misses = [], [], 0, 0.0, 0
        for segments, track in scenes:
            changes = levels(track, method, p)
            onsets, offsets = episodes(segments)
            for on, off in zip(onsets, offsets, strict=True):
                engaged = first(changes, on, Level.ENGAGED, off)
                disengaged = first(changes, off, Level.DISENGAGED, off + 20.0)
                misses += engaged is None
                if engaged is not None:
                    to_engaged.append(engaged)
                if disengaged is not None:
                    to_disengaged.append(disengaged)
            for t, new in changes:
                truth = truth_at(track, t)
                wrong = (truth is False and new is Level.ENGAGED) or (
                    truth is True and new in (Level.DISENGAGING, Level.DISENGAGED)
                )
                spurious += wrong
            minutes += track[-1].t / 60.0
        report[method] = {
            "to_engaged_s": statistics.median(to_engaged) if to_engaged else None,
            "to_disengaged_s": statistics.median(to_disengaged) if to_disengaged else None,
            "spurious_per_person_minute": spurious / minutes,
            "episodes_never_engaged": misses,
            "person_minutes": round(minutes, 1),
        }
    ours = report["ours"]
    report["targets_met"] = {
        "to_engaged_s": ours["to_engaged_s"] is not None
        and ours["to_engaged_s"] <= TARGETS["to_engaged_s"],
        "to_disengaged_s": ours["to_disengaged_s"] is not None
        and ours["to_disengaged_s"] <= TARGETS["to_disengaged_s"],
        "spurious_per_person_minute": ours["spurious_per_person_minute"]
        <= TARGETS["spurious_per_person_minute"],
    }
    return report


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--people", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--quick", action="store_true", help="3 people, for CI")
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args()
    people = 3 if args.quick else args.people
    report = evaluate(people, args.seed, engagement_params(Settings()))
    fmt = lambda v: "never" if v is None else f"{v:.2f}"  # noqa: E731
    print(f"{people} people, {report['ours']['person_minutes']} person-minutes each method")
    print(f"{'':34}{'ours':>10}{'reference':>12}{'target':>10}")
    for key, label in (
        ("to_engaged_s", "starts facing -> ENGAGED (s)"),
        ("to_disengaged_s", "turns away -> DISENGAGED (s)"),
        ("spurious_per_person_minute", "spurious changes / person-min"),
    ):
        print(
            f"{label:34}{fmt(report['ours'][key]):>10}{fmt(report['reference'][key]):>12}"
            f"{TARGETS[key]:>10}"
        )
    print(
        f"{'episodes never ENGAGED':34}{report['ours']['episodes_never_engaged']:>10}"
        f"{report['reference']['episodes_never_engaged']:>12}"
    )
    print(
        "targets: "
        + ", ".join(f"{k} {'met' if v else 'MISSED'}" for k, v in report["targets_met"].items())
    )
    results_file.write(args.out, report, "python -m benchmarks.engagement.simulated", vars(args))


if __name__ == "__main__":
    main()
