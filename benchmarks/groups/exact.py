"""How low the service's assignment takes GCFF's energy: each frame of every shared
sequence grouped by ``groups.detect_centres`` with the shipped parameters (memory off)
three ways, the centres refitted between rounds alike: with the service's assignment
(``facility.assign``: the lowest of every independent part of up to ``MAX_EXACT``
centres, greedy above), with greedy closing everywhere (the assignment before), and with
every round solved by an independent integer-program solver (the facility-location
problem: each person takes one open centre, a centre opened costs the MDL; scipy's
``milp``, HiGHS), which no optimiser of the same energy, GCFF's alpha-expansion
included, can go below.

    python -m benchmarks.groups.exact

Per sequence: frames; the service's rounds, and those whose assignment HiGHS proves
lowest; the frames whose end the service's rounds take lower (higher) than greedy's; the
F1 frame by frame (T = 2/3) of each way.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

import numpy as np
from scipy.optimize import Bounds, LinearConstraint, milp
from scipy.sparse import coo_matrix, hstack, vstack

from facing_service.core.social import facility
from facing_service.core.social import groups as grouping
from facing_service.core.social.groups import GroupParams, members

from .scoring import f1
from .sequence_frame import Frame
from .sequences import SEQUENCES, load

Assign = Callable[[np.ndarray, float, np.ndarray], np.ndarray]


def exact(unary: np.ndarray, mdl: float, rank: np.ndarray) -> np.ndarray:
    """The labels of least energy: minimise sum(unary[i, j] x_ij) + mdl * sum(y_j) with
    sum_j x_ij = 1 and x_ij <= y_j, binary (``rank`` unused: the optimum does not care
    who is listed first)."""
    n, m = unary.shape
    c = np.concatenate([unary.ravel(), np.full(m, mdl)])
    rows = np.repeat(np.arange(n), m)
    one = coo_matrix((np.ones(n * m), (rows, np.arange(n * m))), shape=(n, n * m))
    link_x = coo_matrix((np.ones(n * m), (np.arange(n * m), np.arange(n * m))))
    link_y = coo_matrix((-np.ones(n * m), (np.arange(n * m), np.tile(np.arange(m), n))),
                        shape=(n * m, m))  # fmt: skip
    a = vstack([hstack([one, coo_matrix((n, m))]), hstack([link_x, link_y])]).tocsr()
    lower = np.concatenate([np.ones(n), np.full(n * m, -np.inf)])
    upper = np.concatenate([np.ones(n), np.zeros(n * m)])
    solved = milp(c, constraints=LinearConstraint(a, lower, upper),
                  integrality=np.ones(n * m + m), bounds=Bounds(0, 1))  # fmt: skip
    x = solved.x[: n * m].reshape(n, m)
    return np.argmax(x, axis=1).astype(np.int64)


def energy(frame: Frame, labels: np.ndarray, p: GroupParams) -> float:
    """GCFF's energy of a labelling: unary costs at the labels' refitted centres, plus the
    MDL per label (0 for an empty frame)."""
    if len(labels) == 0:
        return 0.0
    points = grouping.votes(frame.positions, frame.headings, p)
    centre = grouping.centres(points, labels)
    return assignment_energy(grouping._unary(frame.positions, points, centre, p.mdl), labels, p.mdl)


def greedy(unary: np.ndarray, mdl: float, rank: np.ndarray) -> np.ndarray:
    """Greedy closing over the whole room: the assignment before the lowest was sought."""
    every = np.arange(unary.shape[1])
    return facility.take(unary, facility.greedy(unary, mdl, rank), rank, every)


def assignment_energy(unary: np.ndarray, labels: np.ndarray, mdl: float) -> float:
    """The energy of one round's assignment, at that round's centres."""
    return float(unary[np.arange(len(labels)), labels].sum() + mdl * len(set(labels.tolist())))


class Checked:
    """The service's assignment, each round's energy set beside HiGHS's on the same costs."""

    def __init__(self) -> None:
        self.rounds = 0
        self.lowest = 0

    def __call__(self, unary: np.ndarray, mdl: float, rank: np.ndarray) -> np.ndarray:
        labels = facility.assign(unary, mdl, rank)
        proven = assignment_energy(unary, exact(unary, mdl, rank), mdl)
        self.rounds += 1
        self.lowest += assignment_energy(unary, labels, mdl) <= proven + 1e-6
        return labels


def grouped(frame: Frame, solver: Assign, p: GroupParams) -> np.ndarray:
    """``detect_centres``'s labels with ``solver`` as its assignment."""
    kept = grouping.assign
    grouping.assign = solver  # type: ignore[assignment]
    try:
        return grouping.detect_centres(frame.positions, frame.headings, p)[0]
    finally:
        grouping.assign = kept


def found(frame: Frame, labels: np.ndarray) -> list[frozenset[int]]:
    return [frozenset(int(frame.ids[i]) for i in m) for m in members(labels) if len(m) > 1]


def main(argv: list[str] | None = None) -> None:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    p = GroupParams()
    print("sequence | frames | rounds at the lowest | frames lower than greedy (higher) | "
          "F1 greedy / service / HiGHS every round")  # fmt: skip
    for sequence in SEQUENCES:
        frames = load(sequence)
        checked = Checked()
        ways: dict[str, Assign] = {"greedy": greedy, "service": checked, "highs": exact}
        labels = {way: [grouped(f, solve, p) for f in frames] for way, solve in ways.items()}
        ends = {
            way: np.array([energy(f, lab, p) for f, lab in zip(frames, got, strict=True)])
            for way, got in labels.items()
        }
        lower = int((ends["service"] < ends["greedy"] - 1e-9).sum())
        higher = int((ends["service"] > ends["greedy"] + 1e-9).sum())
        scores = [
            f"{f1(frames, [found(f, lab) for f, lab in zip(frames, got, strict=True)], 2 / 3):.3f}"
            for got in labels.values()
        ]
        print(f"{sequence} | {len(frames)} | {checked.lowest}/{checked.rounds} | "
              f"{lower} ({higher}) | {' / '.join(scores)}")  # fmt: skip


if __name__ == "__main__":
    main()
