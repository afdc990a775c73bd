"""The join's cases: one member left out of each annotated group of three or more, and
the two baselines a place is judged beside (the remaining members' centroid, and the
naive slot). Its own module: the join's parameters (``join``) and the join as the
service says it (``join_live``) both read them.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from .sequence_frame import Frame

#: Draws of every bootstrap interval of the join's figures.
BOOTSTRAP = 1000


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
