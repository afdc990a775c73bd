"""Where the robot should stand to join a group, judged on where people really stood
(issues 53, 68).

    python -m benchmarks.groups.join          # choose held out by dataset, print tables
    python -m benchmarks.groups.join --out F  # ... written as JSON (the page's source)
    python -m benchmarks.groups.join --live N --out F  # ... and N cases through the service
    python -m benchmarks.groups.join --page   # docs/groups.md's join tables from it

Leave one member out of a real group (three or more, as annotated in the shared F-formation
sequences; every member in turn, every annotated frame) and ask where a newcomer should
stand: where the left-out member stood is the answer a person gave. The core's join
(``core/social/join.py``, everyone else in the frame as obstacles) with the robot at each
of ``ROBOTS`` around the remaining members (four directions at 2 and 4 m, and far away on
two sides), against two baselines from the same remaining members: their centroid, and
the naive slot (the middle of the largest angular gap around their centroid, at their
mean radius, facing the centroid). Distance and heading error (to the member's annotated
heading), medians with 95 % bootstrap intervals over cases and robot places, the share of
them within 0.5 m, "found": the share given a place (none: no room); and how much the
answer depends on the robot: the range of the medians over the robot's places, over
every case and over the groups with one clear gap.

The join's parameters are chosen with each dataset held out, as the groups' are: among
the candidates that give a place in at least 80 % of the cases of every training
sequence (else the most), the one whose worst training sequence is best, measured as its
median distance over the better baseline's. "Before" is issue 53's rule (the free arc
nearest the robot, ``tie`` 0) with its shipped parameters, on the same cases.
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

from facing_service.core.social.join import JoinParams, chosen, offered

from .. import paths, results_file
from ..sections import generate
from .join_page import tables
from .pair_ring import ring_error
from .sequence_frame import Frame
from .sequences import SEQUENCES, SHARED, load

RESULTS = paths.RESULTS / "join.json"
PAGE = paths.DOCS / "groups.md"
BOOTSTRAP = 1000
FOUND_AT_LEAST = 0.8
ROBOT = (0.0, 0.0)  # the robot at the frame's origin, as the service has it
#: Where the robot stands, from the remaining members' centroid (m): four directions at 2
#: and 4 m, and far away on two sides.
ROBOTS = tuple(
    (r * math.cos(math.radians(a)), r * math.sin(math.radians(a)))
    for r, a in [(d, a) for d in (2.0, 4.0) for a in (0, 90, 180, 270)] + [(30, 45), (30, 225)]
)
#: Issue 53's rule and parameters: the free arc nearest the robot.
BEFORE = JoinParams(tie=0.0, min_radius_m=0.0)


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


def core(case: Case, p: JoinParams) -> list[Place]:
    """The join's place with the robot at each of ``ROBOTS`` (around the members' centroid);
    the group's places worked out once."""
    offer = offered(case.members, case.headings, case.others, p)
    if offer is None:
        return [None] * len(ROBOTS)
    x, y = case.members.mean(axis=0)
    poses = [chosen(offer, (x + dx, y + dy), p) for dx, dy in ROBOTS]
    return [(pose.x, pose.y, pose.yaw) for pose in poses]


def pair_sides(cs: Sequence[Case]) -> dict[str, int]:
    """Of the cases where two members remain: how many put the left-out member more along
    the pair's axis than beside it, how many have headings pointing to a side (their facing
    vectors' sum across the axis), how many of those point to the member's side, and how
    many stand on a ring both face within 45 and 60 degrees (``pair_ring``)."""
    pairs = along = pointing = right = ring_45 = ring_60 = 0
    for c in cs:
        if len(c.members) != 2:
            continue
        a, b = c.members
        axis = (b - a) / np.linalg.norm(b - a)
        across = np.array([-axis[1], axis[0]])
        truth = c.truth - (a + b) / 2
        facing = float(np.column_stack([np.cos(c.headings), np.sin(c.headings)]).sum(0) @ across)
        pairs += 1
        error = ring_error(c.members, c.headings)
        ring_45, ring_60 = ring_45 + (error <= 45), ring_60 + (error <= 60)
        along += abs(truth @ axis) > abs(truth @ across)
        if abs(facing) > 1e-6:
            pointing += 1
            right += (facing > 0) == (truth @ across > 0)
    return {"pairs": pairs, "along": int(along), "pointing": pointing, "right_side": int(right),
            "ring_45": int(ring_45), "ring_60": int(ring_60)}  # fmt: skip


def one_gap(case: Case, p: JoinParams) -> bool:
    """The group leaves one clear arc: where to stand should not depend on the robot."""
    offer = offered(case.members, case.headings, case.others, p)
    return offer is not None and len(offer.places) == 1


def robot_spread(placed: Sequence[list[Place]], cs: Sequence[Case], keep: Sequence[bool]) -> float:
    """How far the median distance moves with where the robot stands (over the cases
    ``keep`` says): the range of the per-robot-place medians."""
    chosen_cases = [c for c, k in zip(cs, keep, strict=True) if k]
    if not chosen_cases:
        return math.nan
    medians = []
    for r in range(len(ROBOTS)):
        found = [places[r] for places, k in zip(placed, keep, strict=True) if k]
        dist, _ = errors(found, chosen_cases)
        medians.append(float(np.median(dist)) if len(dist) else math.nan)
    return float(np.nanmax(medians) - np.nanmin(medians))


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


def pooled(placed: Sequence[list[Place]], cs: Sequence[Case]) -> tuple[list[Place], list[Case]]:
    """Every (case, robot place) pair as one case."""
    return [p for places in placed for p in places], [c for c in cs for _ in ROBOTS]


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
    """The settings compared: the o-space's stride, the clearance (a share of the members'
    spacing; never under 0.3 m, a body's width: a fact about people, not searched), and
    what a near-tie is (arcs within a tenth of the widest, or equal widths only), and the
    ring's least radius (none, or 0.4 m: two people face to face 0.8 m apart). The rule
    itself is not searched: the place is the group's, the robot only breaks ties (issue
    68); issue 53's rule (every arc a tie, the nearest taken) is the "before" beside it."""
    return [
        JoinParams(stride_k=s, clearance_k=c, tie=t, min_radius_m=r)
        for s, c, t, r in itertools.product(
            (0.5, 0.7, 1.0), (0.6, 0.7, 0.8), (0.9, 1.0), (0.0, 0.4)
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
    data = {s: list(cases(load(s, root))) for s in SEQUENCES}
    rng = random.Random(53)
    options = grid()
    best_baseline = {
        s: min(float(np.median(errors([b(c) for c in cs], cs)[0])) for b in (centroid, naive_slot))
        for s, cs in data.items()
    }
    out: dict[str, Any] = {"sequences": {}, "default": asdict(JoinParams()),
                           "settings_compared": len(options), "robots": ROBOTS}  # fmt: skip
    table: dict[tuple[int, str], tuple[float, float]] = {}
    placed: dict[tuple[int, str], list[list[Place]]] = {}
    for i, p in enumerate(options):
        for s, cs in data.items():
            placed[i, s] = [core(c, p) for c in cs]
            dist, _ = errors(*pooled(placed[i, s], cs))
            ratio = float(np.median(dist)) / best_baseline[s] if len(dist) else math.inf
            table[i, s] = (ratio, len(dist) / (len(cs) * len(ROBOTS)))
    for s, cs in data.items():
        held = choose(table, len(options), [o for o in SEQUENCES if SEQUENCES[o] != SEQUENCES[s]])
        before = [core(c, BEFORE) for c in cs]
        gaps = [one_gap(c, options[held]) for c in cs]
        out["sequences"][s] = {
            "dataset": SEQUENCES[s],
            "cases": len(cs),
            "one_gap_cases": sum(gaps),
            "join": figures(*pooled(placed[held, s], cs), rng)
            | {"params": asdict(options[held]),
               "robot_spread_m": robot_spread(placed[held, s], cs, [True] * len(cs)),
               "one_gap_robot_spread_m": robot_spread(placed[held, s], cs, gaps)},
            "before": figures(*pooled(before, cs), rng)
            | {"robot_spread_m": robot_spread(before, cs, [True] * len(cs)),
               "one_gap_robot_spread_m": robot_spread(before, cs, gaps)},
            "centroid": figures([centroid(c) for c in cs], cs, rng),
            "naive_slot": figures([naive_slot(c) for c in cs], cs, rng),
            "pair_sides": pair_sides(cs),
        }  # fmt: skip
    chosen_i = choose(table, len(options), list(SEQUENCES))
    out["chosen_on_all"] = asdict(options[chosen_i])
    every = [d for s, cs in data.items() for d in errors(*pooled(placed[chosen_i, s], cs))[0]]
    out["overall_median_m"] = float(np.median(every))
    return out


BEGIN = "<!-- measured: generated by `python -m benchmarks.groups.join --page` from join.json -->"
END = "<!-- end of join -->"


def page(check: bool) -> int:
    """The page's measured section from the committed results (``sections.generate``)."""
    return generate(
        PAGE, RESULTS, BEGIN, END, tables, check, "python -m benchmarks.groups.join --page"
    )


def live_cases(
    frames: Sequence[Frame], most: int
) -> list[tuple[Frame, Frame, Case, frozenset[int]]]:
    """At most ``most`` leave-one-out cases, evenly spread: each with its whole frame, the
    frame minus the member left out, and the remaining members' ids."""
    every = []
    for f in frames:
        for case, (out, rest) in zip(cases([f]), _left_out(f), strict=True):
            keep = [i for i, pid in enumerate(f.ids) if pid != out]
            shown = Frame(tuple(f.ids[i] for i in keep), f.positions[keep], f.headings[keep], ())
            every.append((f, shown, case, rest))
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


#: The robot's places for the live runs (m from the remaining members' centroid).
LIVE_ROBOTS = ((3.0, 0.0), (0.0, 3.0), (-3.0, 0.0), (0.0, -3.0), (30.0, 30.0))
#: People of different cases never share a name (a group of one case is never taken for
#: another's by the service, nor a place left in one for the next's).
RENAME = 1000


def _placed(frame: Frame, at: np.ndarray, n: int) -> Frame:
    """``frame`` moved so the robot (the origin) stands at ``at`` from it, its people named
    apart from other cases' (``n``)."""
    return Frame(tuple(RENAME * n + i for i in frame.ids), frame.positions - at,
                 frame.headings, ())  # fmt: skip


def evaluate_live(most: int, root: Path = SHARED) -> dict[str, Any]:
    """The shipped join through the live service, both protocols, the robot at each of
    ``LIVE_ROBOTS``: how far from where the member stood, and how far the median moves
    with where the robot stands."""
    from .live import live_said

    out: dict[str, Any] = {}
    for s in SEQUENCES:
        picked = live_cases(load(s, root), most)
        runs: dict[str, list[list[float | None]]] = {"stays": [], "walks_away": []}
        for r, (dx, dy) in enumerate(LIVE_ROBOTS):
            asked = [
                (
                    case,
                    rest,
                    case.members.mean(axis=0) + np.array([dx, dy]),
                    2 * (r * len(picked) + k),
                )
                for k, (_, _, case, rest) in enumerate(picked)
            ]
            stays = [_placed(shown, at, n) for (_, shown, _, _), (_, _, at, n) in zip(
                picked, asked, strict=True)]  # fmt: skip
            walks = [
                frame
                for (whole, shown, _, _), (_, _, at, n) in zip(picked, asked, strict=True)
                for frame in (_placed(whole, at, n + 1), _placed(shown, at, n + 1))
            ]
            said = {"stays": live_said(stays, 0.6),  # the whole frame, then the member gone
                    "walks_away": live_said(walks, 0.6)[1::2]}  # fmt: skip
            for name, offset in (("stays", 0), ("walks_away", 1)):
                runs[name].append(
                    [
                        _distance(groups, case, rest, at, RENAME * (n + offset))
                        for (case, rest, at, n), groups in zip(asked, said[name], strict=True)
                    ]
                )
        out[s] = {
            "cases": len(picked),
            "robots": LIVE_ROBOTS,
            **{name: _live_figures(per_robot) for name, per_robot in runs.items()},
            "centroid_median_m": _median_to_truth(centroid, picked),
            "naive_slot_median_m": _median_to_truth(naive_slot, picked),
        }
    return out


def _distance(
    groups: list[dict], case: Case, rest: frozenset[int], at: np.ndarray, renamed: int
) -> float | None:
    """How far the service's place for the group holding the remaining members is from
    where the left-out member stood (None: no such group, or no place)."""
    names = {f"p{renamed + m}" for m in rest}
    group = next((g for g in groups if names <= set(g["members"])), None)
    if group is None or group["join"] is None:
        return None
    truth = case.truth - at
    return math.hypot(group["join"]["x"] - truth[0], group["join"]["y"] - truth[1])


def _live_figures(per_robot: list[list[float | None]]) -> dict[str, Any]:
    every = [d for run in per_robot for d in run if d is not None]
    medians = [float(np.median(found)) for run in per_robot
               if (found := [d for d in run if d is not None])]  # fmt: skip
    return {
        "placed": len(every) / sum(len(run) for run in per_robot),
        "median_m": float(np.median(every)) if every else None,
        "robot_spread_m": max(medians) - min(medians) if medians else None,
    }


def _median_to_truth(baseline: Any, picked: Sequence[tuple[Frame, Frame, Case, Any]]) -> float:
    return float(np.median([math.hypot(*(np.array(baseline(case)[:2]) - case.truth))
                            for _, _, case, _ in picked]))  # fmt: skip


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
        results["live"] = evaluate_live(args.live)
    command = "python -m benchmarks.groups.join"
    return results_file.report(tables(results), results, args.out, command, vars(args))


if __name__ == "__main__":
    raise SystemExit(main())
