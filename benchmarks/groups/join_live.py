"""Where to stand as the service says it: leave-one-out cases of the shared sequences fed
to the service as a stream (benchmarks.groups.join's cases; ``--live N`` and
``--replayed N`` there).

Two ways through, the same cases and figures: the live service (``live.live_said``: JSON
poses at 30 Hz, the groups queried), and its own scene alone (``replay.said_with_places``:
``FrameScene`` ticked at the service's rate, no zenoh), which gives the same places case for
case (a test holds it) in a fraction of the time, so every case can be measured. The robot
at each of ``LIVE_ROBOTS``: *stays*, each case's frame without the member from the start;
*walks away*, the whole frame, then the member gone. Shares and medians with 95 %
bootstrap intervals over cases (a case's robot places resampled together).
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .join_cases import BOOTSTRAP, Case, cases, centroid, naive_slot
from .sequence_frame import Frame
from .sequences import SEQUENCES, SHARED, load

#: Frames in, each held ``hold_s``: the groups said at the end of each, as published
#: (members ``p<id>``, the robot left out; ``join``: where to stand, or None).
Through = Callable[[Sequence[Frame], float], list[list[dict]]]
HOLD_S = 0.6


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


def evaluate_live(most: int, through: Through, root: Path = SHARED) -> dict[str, Any]:
    """The shipped join as the service says it (``through`` it: live, or its scene
    replayed), the robot at each of ``LIVE_ROBOTS``: how far from where the member stood,
    and how far the median moves with where the robot stands."""
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
            said = {"stays": through(stays, HOLD_S),  # the whole frame, then the member gone
                    "walks_away": through(walks, HOLD_S)[1::2]}  # fmt: skip
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
        **_intervals(per_robot, random.Random(84)),
    }


def _intervals(per_robot: list[list[float | None]], rng: random.Random) -> dict[str, Any]:
    """95 % bootstrap intervals of the share placed and the median, over cases."""
    by_case = list(zip(*per_robot, strict=True))  # each case: its distance per robot place
    shares, medians = [], []
    for _ in range(BOOTSTRAP):
        drawn = [d for _ in by_case for d in by_case[rng.randrange(len(by_case))]]
        found = [d for d in drawn if d is not None]
        shares.append(len(found) / len(drawn))
        medians.append(float(np.median(found)) if found else math.nan)
    lo, hi = int(0.025 * BOOTSTRAP), int(0.975 * BOOTSTRAP) - 1
    shares.sort()
    medians.sort(key=lambda m: (math.isnan(m), m))
    return {"placed_interval": (shares[lo], shares[hi]),
            "median_m_interval": (medians[lo], medians[hi])}  # fmt: skip


def _median_to_truth(baseline: Any, picked: Sequence[tuple[Frame, Frame, Case, Any]]) -> float:
    return float(np.median([math.hypot(*(np.array(baseline(case)[:2]) - case.truth))
                            for _, _, case, _ in picked]))  # fmt: skip
