"""How often a face's facing decision flips on the shared recordings, and what holding it
steady costs on made turn-toward scenes: ``--head-facing-window-s`` chosen by person.

A face tracker's head pose swings tens of degrees from frame to frame (``ghfbv`` in
``2p_AA_FV_eng_1``: about 15° and 55° in turn), which the cone's 5° of hysteresis cannot
hold: the facing decision, and all that is published from it (``/humans/persons/facing``,
who faces whom), flickered with it. The filter: facing by the median angle of the poses
over a window of their stamps, with the cone and its hysteresis as before. The median
follows what most poses say (a swing to one side for a frame or two changes nothing, a
face alternating between two estimates is the one it shows most), and a turn is said
about half the window later.

Judged as the issue's targets say: flips a minute for every person-recording tracked
10 s or more (target at most 5), and the delay added on made scenes of a face turning
toward the robot (target at most 0.5 s). Chosen on all twelve person-recordings (those
tracked under 10 s too: ``ghfbv`` in ``2p_AA_FV_eng_1``, 9.6 s, is the flicker first
reported), leave-one-person-out (the same human across recordings): among the windows
within the delay target, the one with the fewest flips a minute on the other persons'
recordings, or the shortest window whose paired
difference from it has a 95 % bootstrap interval holding 0 (the simpler rule when the
data cannot tell them apart); that person's recordings judged at it.

    python -m benchmarks.engagement.flicker [--out benchmarks/results/flicker.json]
"""

from __future__ import annotations

import argparse
import itertools
import random
import statistics
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from facing_service.config.profiles import tracker_for
from facing_service.config.settings import Settings
from facing_service.contract.keys import BodyRef
from facing_service.contract.poses import Pose, yaw_rotation
from facing_service.contract.stamps import NS_PER_S, Time
from facing_service.core.records import PoseSample

from .. import results_file
from . import replayed
from .scoring import BOOTSTRAP

WINDOWS_S = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
TARGET_FLIPS_PER_MIN = 5.0
TARGET_DELAY_S = 0.5
MIN_TRACKED_S = 10.0
RATE_HZ = 30.0
RESULTS = Path(__file__).resolve().parents[1] / "results" / "flicker.json"


def name(window_s: float) -> str:
    return f"{window_s:g}"


def facing_timelines(
    recording: replayed.Recording, window_s: float
) -> dict[str, list[tuple[int, bool]]]:
    """Each person's published facing decisions (stamp ns, facing) through the tracker a
    service with ``--head-facing-window-s window_s`` runs."""
    tracker = tracker_for(Settings(head_facing_window_s=window_s))
    said: dict[str, list[tuple[int, bool]]] = {}
    for changes in replayed.driven(recording, tracker):
        for state in changes.results:
            said.setdefault(state.body_id, []).append((int(state.stamp), state.facing))
    return said


def flips_per_min(timeline: Sequence[tuple[int, bool]]) -> tuple[float, float]:
    """(flips a minute, seconds tracked) of one person's decisions."""
    flips = sum(a[1] != b[1] for a, b in itertools.pairwise(timeline))
    tracked_s = (timeline[-1][0] - timeline[0][0]) / NS_PER_S if timeline else 0.0
    return (60.0 * flips / tracked_s if tracked_s > 0 else 0.0), tracked_s


def measured(recordings: Sequence[replayed.Recording]) -> list[dict[str, Any]]:
    """Per person-recording: flips a minute under every window (the target is for
    those tracked ``MIN_TRACKED_S`` or more; the others are reported, not chosen on)."""
    rows: dict[tuple[str, str], dict[str, Any]] = {}
    for window in WINDOWS_S:
        for recording in recordings:
            for subject, timeline in facing_timelines(recording, window).items():
                rate, tracked_s = flips_per_min(timeline)
                person = subject.removeprefix("person_")
                row = rows.setdefault(
                    (recording.name, person),
                    {"recording": recording.name, "person": person,
                     "tracked_s": round(tracked_s, 1)},
                )  # fmt: skip
                row[name(window)] = round(rate, 2)
    return list(rows.values())


def turn_scene(window_s: float, distance_m: float, speed_deg_s: float, noise_deg: float,
               seed: int, toward: bool = True) -> float | None:  # fmt: skip
    """A face ``distance_m`` ahead of the robot turning at ``speed_deg_s`` between 60° away
    and straight at it (``toward``, or back away), its yaw with ``noise_deg`` of Gaussian
    jitter a frame: seconds from the moment the noise-free face crosses the 20° cone's
    edge to the moment the published decision is the new one for good (None: never)."""
    tracker = tracker_for(Settings(head_facing_window_s=window_s))
    rng = random.Random(seed)
    crossing_s = (60.0 - 20.0) / speed_deg_s if toward else 20.0 / speed_deg_s
    settled_at, body = None, BodyRef(frame_id="base_link", body_id="f1")
    for i in range(int(4.0 * RATE_HZ)):
        t = i / RATE_HZ
        turned = min(60.0, speed_deg_s * t)
        away = (60.0 - turned if toward else turned) + rng.gauss(0.0, noise_deg)
        stamp = Time(round((1.0 + t) * NS_PER_S))
        pose = Pose(stamp, (distance_m, 0.0, 0.0), yaw_rotation(180.0 + away))
        (state,) = tracker.ingest([PoseSample(body, pose, "head")], 1.0 + t).results
        if state.facing == toward and settled_at is None:
            settled_at = t
        elif state.facing != toward:
            settled_at = None
    return None if settled_at is None else settled_at - crossing_s


def scenes(window_s: float, toward: bool) -> dict[str, Any]:
    """Added delay (against no filter) over made scenes: 1-3 m, 90-360°/s, 0-5° of jitter."""
    added = []
    for distance in (1.0, 2.0, 3.0):
        for speed in (90.0, 180.0, 360.0):
            for noise in (0.0, 2.0, 5.0):
                for seed in range(5):
                    base = turn_scene(0.0, distance, speed, noise, seed, toward)
                    late = turn_scene(window_s, distance, speed, noise, seed, toward)
                    if base is not None and late is not None:
                        added.append(late - base)
    return {"scenes": len(added), "median_s": round(statistics.median(added), 3),
            "max_s": round(max(added), 3)}  # fmt: skip


def interval(values: Sequence[float], seed: int = 0) -> list[float]:
    """A 95 % percentile bootstrap interval of the mean."""
    rng = random.Random(seed)
    means = sorted(statistics.mean(rng.choice(values) for _ in values) for _ in range(BOOTSTRAP))
    return [round(means[int(0.025 * BOOTSTRAP)], 2), round(means[int(0.975 * BOOTSTRAP) - 1], 2)]


def chosen(rows: Sequence[dict[str, Any]], delays: dict[str, float]) -> float:
    """Among the windows saying a made turn toward the robot within ``TARGET_DELAY_S`` at
    worst, the fewest flips a minute on average over ``rows``, or the shortest window not
    told apart from it (the paired difference's interval holds 0)."""
    allowed = [w for w in WINDOWS_S if delays[name(w)] <= TARGET_DELAY_S]
    best = min(allowed, key=lambda w: (statistics.mean(r[name(w)] for r in rows), w))
    for window in allowed:
        differences = [r[name(window)] - r[name(best)] for r in rows]
        if interval(differences)[0] <= 0.0:
            return window
    return best


def held_out(rows: Sequence[dict[str, Any]], delays: dict[str, float]) -> list[dict[str, Any]]:
    """Leave one person out: chosen on the others, the person's rows judged at it."""
    out = []
    for person in sorted({row["person"] for row in rows}):
        window = chosen([row for row in rows if row["person"] != person], delays)
        for row in (r for r in rows if r["person"] == person):
            out.append({"person": person, "recording": row["recording"], "window_s": window,
                        "flips_per_min": row[name(window)], "before": row[name(0.0)]})  # fmt: skip
    return out


def evaluate() -> dict[str, Any]:
    rows = measured(replayed.load())
    per: dict[str, Any] = {}
    for window in WINDOWS_S:
        flips = [r[name(window)] for r in rows]
        judged = [r[name(window)] for r in rows if r["tracked_s"] >= MIN_TRACKED_S]
        per[name(window)] = {
            "flips_per_min_mean": round(statistics.mean(flips), 2),
            "flips_per_min_ci": interval(flips),
            "flips_per_min_worst": max(flips),
            "tracked_10_s_worst": max(judged),
            "tracked_10_s_within_target": sum(f <= TARGET_FLIPS_PER_MIN for f in judged),
            "tracked_10_s": len(judged),
            "toward": scenes(window, True),
            "away": scenes(window, False),
        }
    delays = {n: d["toward"]["max_s"] for n, d in per.items()}
    return {"rows": rows, "windows": per, "held_out": held_out(rows, delays),
            "chosen_on_all": chosen(rows, delays)}  # fmt: skip


def print_results(results: dict[str, Any]) -> None:
    print("window s | flips/min mean [95 % CI] | worst | tracked >= 10 s: worst, within 5 | "
          "added delay, turning toward (median / max) | turning away (median / max)")  # fmt: skip
    for c, d in results["windows"].items():
        toward, away = d["toward"], d["away"]
        print(f"{c:>8} | {d['flips_per_min_mean']:6.2f} {d['flips_per_min_ci']} | "
              f"{d['flips_per_min_worst']:6.2f} | {d['tracked_10_s_worst']:6.2f}, "
              f"{d['tracked_10_s_within_target']}/{d['tracked_10_s']} | {toward['median_s']:.2f} / "
              f"{toward['max_s']:.2f} s | {away['median_s']:.2f} / "
              f"{away['max_s']:.2f} s")  # fmt: skip
    print("\nheld out by person: recording, person, chosen without them, flips/min "
          "before -> after")  # fmt: skip
    for row in results["held_out"]:
        print(f"  {row['recording']:<16} {row['person']:<6} {row['window_s']:<5} "
              f"{row['before']:7.2f} -> {row['flips_per_min']:.2f}")  # fmt: skip
    shipped = name(results["chosen_on_all"])
    print(f"\nchosen on every person: {shipped} s; every person-recording, flips/min "
          "before -> after at it (tracked s)")  # fmt: skip
    for row in results["rows"]:
        print(f"  {row['recording']:<16} {row['person']:<6} {row['0']:7.2f} -> "
              f"{row[shipped]:6.2f} ({row['tracked_s']} s)")  # fmt: skip


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, help=f"write the figures (e.g. {RESULTS})")
    args = parser.parse_args(argv)
    results = evaluate()
    print_results(results)
    if args.out is not None:
        results_file.write(args.out, results, "python -m benchmarks.engagement.flicker",
                           vars(args), indent=1)  # fmt: skip


if __name__ == "__main__":
    main()
