"""F-formations scored as GCFF scores them (its ``ff_evalgroups``, franzsetti/GCFF, MIT),
with 95 % bootstrap intervals over a sequence's frames."""

from __future__ import annotations

import random
import statistics
from collections.abc import Sequence

import numpy as np

from .sequence_frame import Frame

BOOTSTRAP = 1000


def evalgroups(found: Sequence[frozenset[int]], truth: Sequence[frozenset[int]], th: float):
    """GCFF's ff_evalgroups (cardinality mode off): precision, recall of one frame."""
    if not found and not truth:
        return 1.0, 1.0
    if not found:
        return 1.0, 0.0
    if not truth:
        return 0.0, 1.0
    tp = 0
    for t in truth:
        for g in found:
            if len(t & g) / max(len(t), len(g)) >= th:
                tp += 1
                break
    return tp / len(found), tp / len(truth)


def scores(
    frames: Sequence[Frame], found: Sequence[Sequence[frozenset[int]]], th: float
) -> np.ndarray:
    """(frames, 2): each frame's precision and recall."""
    return np.array([evalgroups(g, f.truth, th) for f, g in zip(frames, found, strict=True)])


def f1_of(per_frame: np.ndarray) -> float:
    """F1 from the mean precision and recall over frames (GCFF's way)."""
    pr, re = per_frame.mean(axis=0)
    return 0.0 if pr + re == 0 else float(2 * pr * re / (pr + re))


def f1(frames: Sequence[Frame], found: Sequence[Sequence[frozenset[int]]], th: float) -> float:
    return f1_of(scores(frames, found, th))


def interval(per_frame: np.ndarray, rng: random.Random) -> tuple[float, float]:
    """95 % bootstrap interval of F1 over frames."""
    n = len(per_frame)
    draws = sorted(f1_of(per_frame[[rng.randrange(n) for _ in range(n)]]) for _ in range(BOOTSTRAP))
    return draws[int(0.025 * BOOTSTRAP)], draws[int(0.975 * BOOTSTRAP) - 1]


def difference(a: np.ndarray, b: np.ndarray, rng: random.Random) -> tuple[float, float, float]:
    """F1(a) - F1(b) on the same frames, and its 95 % paired bootstrap interval."""
    n = len(a)
    draws = []
    for _ in range(BOOTSTRAP):
        pick = [rng.randrange(n) for _ in range(n)]
        draws.append(f1_of(a[pick]) - f1_of(b[pick]))
    draws.sort()
    return f1_of(a) - f1_of(b), draws[int(0.025 * BOOTSTRAP)], draws[int(0.975 * BOOTSTRAP) - 1]


#: Each candidate's per-frame precision and recall on each sequence, keyed (candidate's
#: index, sequence): (T = 2/3, T = 1).
Scores = dict[tuple[int, str], tuple[np.ndarray, np.ndarray]]


def choose(table: Scores, indices: Sequence[int], training: Sequence[str]) -> int:
    """The candidate whose worst training sequence scores best (F1, T = 2/3); ties by mean."""

    def worth(i: int) -> tuple[float, float]:
        figures = [f1_of(table[i, s][0]) for s in training]
        return min(figures), statistics.mean(figures)

    return max(indices, key=worth)
