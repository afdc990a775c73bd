"""Where the robot should stand to join a group, judged on where people really stood
(issue 53).

    python -m benchmarks.groups.join          # choose held out by dataset, print tables
    python -m benchmarks.groups.join --out F  # ... written as JSON (the page's source)
    python -m benchmarks.groups.join --page   # docs/groups.md's join tables from it

Leave one member out of a real group (three or more, as annotated in the shared F-formation
sequences; every member in turn, every annotated frame) and ask where a newcomer should
stand: where the left-out member stood is the answer a person gave. The core's join
(``core/join.py``, the robot at the frame's origin as on a robot, everyone else in the
frame as obstacles) against two baselines from the same remaining members: their centroid,
and the naive slot (the middle of the largest angular gap around their centroid, at their
mean radius, facing the centroid). Distance and heading error (to the member's annotated
heading), medians with 95 % bootstrap intervals over cases, and the share of cases within
0.5 m; "found" is the share of cases given a place (none: no room).

The join's parameters are chosen with each dataset held out, as the groups' are: among
the candidates that give a place in at least 80 % of the cases of every training
sequence (else the most), the one whose worst training sequence is best, measured as its
median distance over the better baseline's.
"""

from __future__ import annotations

import argparse
import itertools
import math
import random
import statistics
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from facing_service.core.social.join import JoinParams, join_pose

from .. import paths, results_file
from ..sections import generate
from .held_out import SEQUENCES, SHARED, load
from .sequence_frame import Frame

RESULTS = paths.RESULTS / "join.json"
PAGE = paths.DOCS / "groups.md"
BOOTSTRAP = 1000
FOUND_AT_LEAST = 0.8
ROBOT = (0.0, 0.0)  # the robot at the frame's origin, as the service has it


@dataclass(frozen=True)
class Case:
    """One member left out of one annotated group."""

    members: np.ndarray  # (n, 2) the remaining members
    headings: np.ndarray  # (n,)
    others: np.ndarray  # (m, 2) everyone else in the frame
    truth: np.ndarray  # (2,) where the left-out member stood
    truth_heading: float


def cases(frames: Sequence[Frame]) -> Iterator[Case]:
    for f in frames:
        index = {pid: i for i, pid in enumerate(f.ids)}
        for group in f.truth:
            if len(group) < 3:
                continue
            for out in sorted(group):
                rest = [index[m] for m in sorted(group) if m != out and m in index]
                if out not in index or len(rest) < 2:
                    continue
                others = [i for i in range(len(f.ids)) if i != index[out] and i not in rest]
                yield Case(
                    f.positions[rest],
                    f.headings[rest],
                    f.positions[others],
                    f.positions[index[out]],
                    float(f.headings[index[out]]),
                )


Place = tuple[float, float, float] | None  # (x, y, yaw), None: no place given


def centroid(case: Case) -> Place:
    c = case.members.mean(axis=0)
    return float(c[0]), float(c[1]), 0.0  # no heading: it says where, not which way


def naive_slot(case: Case) -> Place:
    c = case.members.mean(axis=0)
    radius = float(np.hypot(*(case.members - c).T).mean())
    angles = np.sort(np.mod(np.arctan2(*(case.members - c)[:, ::-1].T), 2 * math.pi))
    gaps = np.diff(np.append(angles, angles[0] + 2 * math.pi))
    k = int(np.argmax(gaps))
    middle = angles[k] + gaps[k] / 2
    x, y = c[0] + radius * math.cos(middle), c[1] + radius * math.sin(middle)
    return float(x), float(y), math.atan2(c[1] - y, c[0] - x)


def core(case: Case, p: JoinParams) -> Place:
    pose = join_pose(case.members, case.headings, case.others, ROBOT, p)
    return None if pose is None else (pose.x, pose.y, pose.yaw)


def errors(found: Sequence[Place], all_cases: Sequence[Case]) -> tuple[np.ndarray, np.ndarray]:
    """Distance (m) and heading error (degrees) of every case given a place."""
    dist, head = [], []
    for place, case in zip(found, all_cases, strict=True):
        if place is None:
            continue
        dist.append(math.hypot(place[0] - case.truth[0], place[1] - case.truth[1]))
        head.append(abs(math.degrees(math.remainder(place[2] - case.truth_heading, math.tau))))
    return np.array(dist), np.array(head)


def median_interval(values: np.ndarray, rng: random.Random) -> tuple[float, float]:
    n = len(values)
    if n == 0:
        return math.nan, math.nan
    draws = sorted(
        float(np.median(values[[rng.randrange(n) for _ in range(n)]])) for _ in range(BOOTSTRAP)
    )
    return draws[int(0.025 * BOOTSTRAP)], draws[int(0.975 * BOOTSTRAP) - 1]


def figures(found: Sequence[Place], all_cases: Sequence[Case], rng: random.Random) -> dict:
    dist, head = errors(found, all_cases)
    return {
        "found": len(dist) / len(all_cases),
        "median_m": float(np.median(dist)) if len(dist) else None,
        "median_m_interval": median_interval(dist, rng),
        "within_half_m": float((dist <= 0.5).mean()) if len(dist) else 0.0,
        "heading_deg": float(np.median(head)) if len(head) else None,
    }


def grid() -> list[JoinParams]:
    return [
        JoinParams(stride_k=s, clearance_k=c, min_clearance_m=m, several=w)
        for s, c, m, w in itertools.product(
            (0.5, 0.7, 1.0), (0.6, 0.7, 0.8), (0.3, 0.5), (0.0, 0.75, 1.0)
        )
    ]


def choose(
    table: dict[tuple[int, str], tuple[float, float]], options: int, training: Sequence[str]
) -> int:
    """The candidate whose worst training sequence is best (median distance over the better
    baseline's), among those giving a place in FOUND_AT_LEAST of every training sequence's
    cases (when any does)."""

    def enough(i: int) -> bool:
        return all(table[i, s][1] >= FOUND_AT_LEAST for s in training)

    eligible = [i for i in range(options) if enough(i)] or list(range(options))
    return min(
        eligible,
        key=lambda i: (
            max(table[i, s][0] for s in training),
            statistics.mean(table[i, s][0] for s in training),
        ),
    )


def evaluate(root: Path = SHARED) -> dict[str, Any]:
    data = {s: list(cases(load(s, root, every=1))) for s in SEQUENCES}
    rng = random.Random(53)
    options = grid()
    baselines = {s: (centroid, naive_slot) for s in data}
    best_baseline = {}
    out: dict[str, Any] = {"sequences": {}, "default": asdict(JoinParams())}
    for s, cs in data.items():
        medians = [float(np.median(errors([b(c) for c in cs], cs)[0])) for b in baselines[s]]
        best_baseline[s] = min(medians)
    table: dict[tuple[int, str], tuple[float, float]] = {}
    placed: dict[tuple[int, str], list[Place]] = {}
    for i, p in enumerate(options):
        for s, cs in data.items():
            found = placed[i, s] = [core(c, p) for c in cs]
            dist, _ = errors(found, cs)
            ratio = float(np.median(dist)) / best_baseline[s] if len(dist) else math.inf
            table[i, s] = (ratio, len(dist) / len(cs))
    for s, cs in data.items():
        held = choose(table, len(options), [o for o in SEQUENCES if SEQUENCES[o] != SEQUENCES[s]])
        out["sequences"][s] = {
            "dataset": SEQUENCES[s],
            "cases": len(cs),
            "join": figures(placed[held, s], cs, rng) | {"params": asdict(options[held])},
            "centroid": figures([centroid(c) for c in cs], cs, rng),
            "naive_slot": figures([naive_slot(c) for c in cs], cs, rng),
        }
    chosen = choose(table, len(options), list(SEQUENCES))
    out["chosen_on_all"] = asdict(options[chosen])
    every = [d for s, cs in data.items() for d in errors(placed[chosen, s], cs)[0]]
    out["overall_median_m"] = float(np.median(every))
    return out


def _m(value: float | None) -> str:
    return "—" if value is None or math.isnan(value) else f"{value:.2f}"


def _deg(value: float | None) -> str:
    return "—" if value is None else f"{value:.0f}"


def tables(results: dict[str, Any]) -> list[str]:
    lines = [
        "Each member of each annotated group of three or more left out in turn, the join"
        " held out by dataset (its parameters chosen on the other datasets), against the two"
        " baselines on the same cases: median distance to where the member stood [95 %"
        " interval], share within 0.5 m, median heading error, share of cases given a place:",
        "",
        "| sequence | cases | join: found | median m | within 0.5 m | heading ° | centroid m"
        " | naive slot m | within 0.5 m | heading ° |",
        "| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for s, r in results["sequences"].items():
        j, c, n = r["join"], r["centroid"], r["naive_slot"]
        lo, hi = j["median_m_interval"]
        lines.append(
            f"| {s} | {r['cases']} | {j['found']:.0%} | **{_m(j['median_m'])}** [{_m(lo)},"
            f" {_m(hi)}] | {j['within_half_m']:.0%} | {_deg(j['heading_deg'])}"
            f" | {_m(c['median_m'])} | {_m(n['median_m'])} | {n['within_half_m']:.0%}"
            f" | {_deg(n['heading_deg'])} |"
        )
    if "live" in results:
        lines += [
            "",
            "The shipped join through the live service (each case's frame, the member left out,"
            " held 0.6 s as JSON poses at 30 Hz; `hri/groups/<frame>` queried at its end): a"
            " place is given only for a group the service found (holding the remaining"
            " members); its distance to where the member stood, beside the centroid's and the"
            " naive slot's on the same cases, and against the core's place for the same people:",
            "",
            "| sequence | cases | given a place | median m | centroid m | naive slot m"
            " | live - core, worst m |",
            "| --- | ---: | ---: | ---: | ---: | ---: | ---: |",
        ]
        for s, r in results["live"].items():
            lines.append(
                f"| {s} | {r['cases']} | {r['placed']:.0%} | {_m(r['median_m'])}"
                f" | {_m(r.get('centroid_median_m'))} | {_m(r.get('naive_slot_median_m'))}"
                f" | {_m(r['live_minus_core_m'])} |"
            )
    d = results["chosen_on_all"]
    lines += [
        "",
        f"Overall median (the set chosen on all six): {results['overall_median_m']:.2f} m."
        f" The shipped set: stride {d['stride_k']:g}x the members' spacing, clearance"
        f" {d['clearance_k']:g}x their nearest spacing and at least {d['min_clearance_m']:g} m,"
        + (
            " the nearest free arc."
            if d["several"] == 0
            else f" the nearest of the arcs at least {d['several']:g} of the widest."
        ),
    ]
    return lines


BEGIN = "<!-- measured: generated by `python -m benchmarks.groups.join --page` from join.json -->"
END = "<!-- end of join -->"


def page(check: bool) -> int:
    """The page's measured section from the committed results (``sections.generate``)."""
    return generate(
        PAGE, RESULTS, BEGIN, END, tables, check, "python -m benchmarks.groups.join --page"
    )


def live_cases(frames: Sequence[Frame], most: int) -> list[tuple[Frame, Case, frozenset[int]]]:
    """At most ``most`` leave-one-out cases, evenly spread: each with its frame minus the
    member left out (what the live service is shown) and the remaining members' ids."""
    every = []
    for f in frames:
        for case, (out, rest) in zip(cases([f]), _left_out(f), strict=True):
            keep = [i for i, pid in enumerate(f.ids) if pid != out]
            shown = Frame(tuple(f.ids[i] for i in keep), f.positions[keep], f.headings[keep], ())
            every.append((shown, case, rest))
    step = max(1, len(every) // most)
    return every[::step][:most]


def _left_out(f: Frame) -> Iterator[tuple[int, frozenset[int]]]:
    """The member each of ``cases([f])`` leaves out, and the others, in the same order."""
    present = set(f.ids)
    for group in f.truth:
        if len(group) < 3:
            continue
        for out in sorted(group):
            rest = frozenset(m for m in group if m != out and m in present)
            if out in present and len(rest) >= 2:
                yield out, rest


def evaluate_live(most: int, hold_s: float, root: Path = SHARED) -> dict[str, Any]:
    """The shipped join through the live service (JSON poses at 30 Hz, each case's frame
    held ``hold_s``, ``hri/groups/<frame>`` queried at its end) beside the core on the
    group the service found: where the service says to stand is where the core says, for
    the same people; and how far from where the member stood."""
    from .live import live_said

    out: dict[str, Any] = {}
    for s in SEQUENCES:
        picked = live_cases(load(s, root, every=1), most)
        said = live_said([shown for shown, _, _ in picked], hold_s)
        to_truth, to_core, placed = [], [], 0
        baselines: dict[str, list[float]] = {"centroid": [], "naive_slot": []}
        for (shown, case, rest), groups in zip(picked, said, strict=True):
            group = next((g for g in groups if rest <= {int(m[1:]) for m in g["members"]}), None)
            if group is None or group["join"] is None:
                continue
            placed += 1
            join = group["join"]
            to_truth.append(math.hypot(join["x"] - case.truth[0], join["y"] - case.truth[1]))
            for name, baseline in (("centroid", centroid), ("naive_slot", naive_slot)):
                where = baseline(case)  # the same case, the same remaining members
                baselines[name].append(
                    math.hypot(where[0] - case.truth[0], where[1] - case.truth[1])
                )
            inside = [i for i, pid in enumerate(shown.ids) if f"p{pid}" in group["members"]]
            others = [i for i in range(len(shown.ids)) if i not in inside]
            core_pose = join_pose(shown.positions[inside], shown.headings[inside],
                                  shown.positions[others], ROBOT, JoinParams())  # fmt: skip
            if core_pose is not None:
                to_core.append(math.hypot(join["x"] - core_pose.x, join["y"] - core_pose.y))
        out[s] = {
            "cases": len(picked),
            "placed": placed / len(picked),
            "median_m": float(np.median(to_truth)) if to_truth else None,
            **{
                f"{name}_median_m": float(np.median(d)) if d else None
                for name, d in baselines.items()
            },
            "live_minus_core_m": float(np.max(to_core)) if to_core else None,
            "hold_s": hold_s,
        }
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="write the results as JSON")
    parser.add_argument(
        "--live", type=int, metavar="N", help="also N cases a sequence through the live service"
    )
    parser.add_argument("--page", action="store_true", help="rewrite docs/groups.md's join table")
    parser.add_argument("--check", action="store_true", help="with --page: exit 1 if stale")
    args = parser.parse_args(argv)
    if args.page:
        return page(args.check)
    if args.live is not None and not 1 <= args.live <= 1000:
        parser.error(f"--live must be a number of cases from 1 to 1000, got {args.live}")
    results = evaluate()
    if args.live:
        results["live"] = evaluate_live(args.live, hold_s=0.6)
    print("\n".join(tables(results)))
    if args.out is not None:
        results_file.write(args.out, results, "python -m benchmarks.groups.join", vars(args))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
