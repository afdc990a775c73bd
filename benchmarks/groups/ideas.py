"""Ideas for dense rooms measured beside the shipped rule, kept or dropped on their figures:
each a filter on the groups the core finds, with one parameter, scored on every shared
sequence and on the scenes made for the failures (``scenes``).

    python -m benchmarks.groups.ideas

- **Members face their o-space**: a member whose heading is more than ``limit`` degrees
  from the direction to the group's centre (the mean of its members' positions; for a
  pair, the other member) leaves it, until every member faces in. Aimed at loners grouped
  by their positions alone.
- **A pair's votes converge**: two people are a group only when their o-space votes are
  closer than ``ratio`` times their own distance (people facing a shared space vote
  nearer each other than they stand). Aimed at side-by-side loners.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Callable, Sequence

import numpy as np

from facing_service.core.social.groups import (
    GroupParams,
    RoomScale,
    ScaleParams,
    detect,
    groups,
    votes,
)

from .held_out import FRAME_S
from .scenes import scenes
from .scoring import f1
from .sequence_frame import Frame
from .sequences import SEQUENCES, load

Filter = Callable[[list[int], np.ndarray, np.ndarray, np.ndarray], list[int]]


def faces_its_space(limit_deg: float) -> Filter:
    def keep(group: list[int], pos: np.ndarray, head: np.ndarray, _votes: np.ndarray) -> list[int]:
        while len(group) > 1:
            facing = []
            for i in group:
                others = [j for j in group if j != i]
                target = pos[others[0]] if len(group) == 2 else pos[group].mean(axis=0)
                d = target - pos[i]
                off = abs(math.remainder(math.atan2(d[1], d[0]) - head[i], math.tau))
                if math.degrees(off) <= limit_deg:
                    facing.append(i)
            if len(facing) == len(group):
                break
            group = facing
        return group

    return keep


def pairs_converge(ratio: float) -> Filter:
    def keep(group: list[int], pos: np.ndarray, _head: np.ndarray, vote: np.ndarray) -> list[int]:
        if len(group) != 2:
            return group
        i, j = group
        close = np.hypot(*(vote[i] - vote[j])) <= ratio * np.hypot(*(pos[i] - pos[j]))
        return group if close else []

    return keep


def run_filtered(frames: Sequence[Frame], keep: Filter | None) -> list[list[frozenset[int]]]:
    """``groups.run`` with the shipped defaults, each group passed through ``keep``."""
    p, room = GroupParams(), RoomScale(ScaleParams())
    out = []
    for k, f in enumerate(frames):
        unit = room.observe(f.positions, k * FRAME_S)
        pos = np.vstack([f.positions, [[0.0, 0.0]]])
        head = np.append(f.headings, 0.0)
        vote = votes(pos / unit, head, p) * unit
        found = []
        for g in groups(detect(pos, head, p, unit)):
            people = [i for i in g if i < len(f.ids)]  # the robot is no person
            if keep is not None:
                people = keep(people, pos, head, vote)
            if len(people) > 1:
                found.append(frozenset(f.ids[i] for i in people))
        out.append(found)
    return out


IDEAS: dict[str, Filter | None] = {
    "shipped rule": None,
    **{f"members face their o-space, {d}°": faces_its_space(d) for d in (90, 120, 135)},
    **{f"a pair's votes converge, ratio {r:g}": pairs_converge(r) for r in (1.0, 0.9, 0.8)},
}


def main() -> int:
    shared = {s: load(s) for s in SEQUENCES}
    made = scenes()
    print("| idea | " + " | ".join([*shared, *made]) + " | shared mean |")
    print("| --- |" + " ---: |" * (len(shared) + len(made) + 1))
    for name, keep in IDEAS.items():
        ours = [f1(fr, run_filtered(fr, keep), 2 / 3) for fr in shared.values()]
        theirs = [f1(fr, run_filtered(fr, keep), 2 / 3) for fr in made.values()]
        cells = " | ".join(f"{x:.2f}" for x in [*ours, *theirs])
        print(f"| {name} | {cells} | {statistics.mean(ours):.3f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
