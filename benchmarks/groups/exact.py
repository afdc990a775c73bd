"""How far the greedy assignment is from GCFF's energy's optimum, and what the optimum
groups: each frame of every shared sequence grouped by ``groups.detect_centres`` with the
shipped parameters (memory off), once with the service's greedy ``facility.assign`` and
once with the assignment solved exactly at every round (the facility-location problem
as an integer program: each person takes one open centre, a centre opened costs the MDL;
scipy's ``milp``, HiGHS), the centres refitted between rounds the same way.

    python -m benchmarks.groups.exact

Per sequence: frames, the share where the exact rounds end at a lower energy than the
greedy ones, the mean energy saved, and the F1 frame by frame (T = 2/3) of each. With the
parameters chosen for the greedy pass: what the solver alone changes, before any
parameter is chosen again with it.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

import numpy as np
from scipy.optimize import Bounds, LinearConstraint, milp
from scipy.sparse import coo_matrix, hstack, vstack

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
    unary = grouping._unary(frame.positions, points, centre, p.mdl)
    return float(unary[np.arange(len(labels)), labels].sum() + p.mdl * (labels.max() + 1))


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
    print("sequence | frames | exact lower | energy saved (mean) | F1 greedy -> exact")
    for sequence in SEQUENCES:
        frames = load(sequence)
        greedy_found, exact_found, lower, saved = [], [], 0, []
        for frame in frames:
            g, e = grouped(frame, grouping.assign, p), grouped(frame, exact, p)
            eg, ee = energy(frame, g, p), energy(frame, e, p)
            lower += ee < eg - 1e-9
            saved.append(eg - ee)
            greedy_found.append(found(frame, g))
            exact_found.append(found(frame, e))
        print(
            f"{sequence} | {len(frames)} | {lower} | {np.mean(saved):.4f} | "
            f"{f1(frames, greedy_found, 2 / 3):.3f} -> {f1(frames, exact_found, 2 / 3):.3f}"
        )


if __name__ == "__main__":
    main()
