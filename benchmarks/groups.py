"""F-formations on the shared benchmark sequences, scored as GCFF scores them.

    python -m benchmarks.groups            # per sequence: one parameter set, and tuned
    python -m benchmarks.groups --live     # ... and the default through the live service

The sequences (../shared/data/fformations: CoffeeBreak Seq1, Seq2, Synth; read from there,
never copied) give per annotated frame each person's id, position (cm) and heading, and
the true groups. Scored as GCFF's ``ff_evalgroups`` (franzsetti/GCFF, MIT): singletons
dropped from both sides; a detected group is right when |G ∩ T| / max(|G|, |T|) >= T
(2/3, and 1); precision and recall per frame (an empty detection scores precision 1,
so the "no groups" floor is printed beside every figure), averaged over the frames; F1
from those means.

One parameter set for every scene (a service cannot retune per room), chosen by
leave-one-sequence-out: for each sequence, the candidate best on the other two (mean F1
at T = 2/3) is scored on it. The per-scene-tuned figures are printed beside it, and
GCFF's own (its code, run unchanged, issue 33).
"""

from __future__ import annotations

import argparse
import itertools
import json
import statistics
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from facing_service.core.groups import GroupParams, detect, groups

SHARED = Path(__file__).resolve().parents[2] / "shared" / "data" / "fformations"
SEQUENCES = ("CoffeeBreak/Seq1", "CoffeeBreak/Seq2", "Synth")
CM = 0.01
#: GCFF's figures, its code run unchanged and scored by its ff_evalgroups (issue 33):
#: F1 at T = 2/3 tuned per scene, at T = 1 tuned, at T = 2/3 with one set chosen without
#: that sequence.
GCFF = {
    "CoffeeBreak/Seq1": (0.77, 0.45, 0.63),
    "CoffeeBreak/Seq2": (0.94, 0.73, 0.86),
    "Synth": (0.97, 0.91, 0.62),
}
#: Candidates: each person's stride from the nearest person ahead (``stride_k`` times it,
#: within [``stride_min_m``, ``stride_max_m``], "ahead" within ``cone_deg``), the cost of
#: a group (m²); and GCFF's own rule (one stride for everyone) beside them.
GRID = {
    "stride_k": (0.3, 0.4, 0.5),
    "stride_min_m": (0.2, 0.3),
    "stride_max_m": (0.5, 0.6, 0.7),
    "cone_deg": (45.0, 70.0),
    "mdl_m2": (0.6, 0.8, 1.0),
}
GCFF_GRID = {"stride_m": (0.3, 0.4, 0.5, 0.6), "mdl_m2": (0.4, 0.6, 0.8, 1.0)}


@dataclass(frozen=True)
class Frame:
    ids: tuple[int, ...]
    positions: np.ndarray  # (N, 2) metres
    headings: np.ndarray  # (N,) radians
    truth: tuple[frozenset[int], ...]  # groups of two or more


def load(sequence: str, root: Path = SHARED) -> list[Frame]:
    """The annotated frames of a sequence, in metres."""
    from scipy.io import loadmat  # MATLAB v5 cell arrays: scipy reads them, we would not

    folder = root / sequence
    features = loadmat(folder / "features.mat")
    truth = loadmat(folder / "groundtruth.mat")
    by_stamp = {
        int(stamp): cell for stamp, cell in zip(
            np.ravel(features["timestamp"]), np.ravel(features["features"]), strict=True)
    }  # fmt: skip
    frames = []
    for stamp, cell in zip(
        np.ravel(truth["GTtimestamp"]), np.ravel(truth["GTgroups"]), strict=True
    ):
        f = np.asarray(by_stamp[int(stamp)], dtype=np.float64).reshape(-1, 4)
        true = tuple(
            frozenset(int(x) for x in np.ravel(g)) for g in np.ravel(cell) if np.size(g) > 1
        )
        frames.append(Frame(tuple(int(i) for i in f[:, 0]), f[:, 1:3] * CM, f[:, 3], true))
    return frames


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


def f1(frames: Sequence[Frame], found: Sequence[Sequence[frozenset[int]]], th: float) -> float:
    scores = [evalgroups(g, f.truth, th) for f, g in zip(frames, found, strict=True)]
    pr = statistics.mean(s[0] for s in scores)
    re = statistics.mean(s[1] for s in scores)
    return 0.0 if pr + re == 0 else 2 * pr * re / (pr + re)


def run(frames: Sequence[Frame], p: GroupParams) -> list[list[frozenset[int]]]:
    out = []
    for f in frames:
        labels = detect(f.positions, f.headings, p)
        out.append([frozenset(f.ids[i] for i in g) for g in groups(labels)])
    return out


def candidates() -> list[GroupParams]:
    """The adaptive-stride grid, then GCFF's fixed-stride rule."""
    names = list(GRID)
    adaptive = [
        GroupParams(**dict(zip(names, values, strict=True)))
        for values in itertools.product(*GRID.values())
    ]
    fixed = [GroupParams.gcff(*values) for values in itertools.product(*GCFF_GRID.values())]
    return adaptive + fixed


def is_gcff_rule(p: GroupParams) -> bool:
    return p.stride_min_m == p.stride_max_m


def evaluate(root: Path = SHARED) -> dict[str, Any]:
    """Every candidate on every sequence; per rule (the adaptive stride, GCFF's fixed
    one), per sequence, the set chosen without it and the set tuned on it."""
    data = {s: load(s, root) for s in SEQUENCES}
    options = candidates()
    table = {s: [] for s in SEQUENCES}  # per sequence: (F1 2/3, F1 1) per candidate
    for p in options:
        for s, frames in data.items():
            found = run(frames, p)
            table[s].append((f1(frames, found, 2 / 3), f1(frames, found, 1.0)))
    rules = {
        "adaptive": [i for i, p in enumerate(options) if not is_gcff_rule(p)],
        "gcff_rule": [i for i, p in enumerate(options) if is_gcff_rule(p)],
    }
    out: dict[str, Any] = {"sequences": {}, "default": {}}
    for s, frames in data.items():
        others = [o for o in SEQUENCES if o != s]
        row: dict[str, Any] = {
            "no_groups_floor": f1(frames, [[] for _ in frames], 2 / 3),
            "gcff": GCFF[s],
            "frames": len(frames),
        }
        for rule, indices in rules.items():
            chosen = max(indices, key=lambda i: statistics.mean(table[o][i][0] for o in others))
            tuned = max(indices, key=lambda i: table[s][i][0])
            row[rule] = {
                "one_set": _figures(options[chosen], table[s][chosen]),
                "tuned": _figures(options[tuned], table[s][tuned]),
            }
        out["sequences"][s] = row
    for rule, indices in rules.items():
        best = max(indices, key=lambda i: statistics.mean(table[s][i][0] for s in SEQUENCES))
        out["default"][rule] = asdict(options[best])
    return out


def _figures(p: GroupParams, scores: tuple[float, float]) -> dict[str, Any]:
    return {"params": asdict(p), "f1_23": scores[0], "f1_1": scores[1]}


def print_results(results: dict[str, Any]) -> None:
    print(
        f"{'sequence':18} {'rule':10} {'one set 2/3':>11} {'1':>6} {'tuned 2/3':>10} {'1':>6}"
        f" {'GCFF tuned 2/3':>15} {'1':>6} {'GCFF one set':>13} {'no groups':>10}"
    )
    for s, r in results["sequences"].items():
        g = r["gcff"]
        for rule in ("adaptive", "gcff_rule"):
            one, tuned = r[rule]["one_set"], r[rule]["tuned"]
            print(
                f"{s:18} {rule:10} {one['f1_23']:11.2f} {one['f1_1']:6.2f} "
                f"{tuned['f1_23']:10.2f} {tuned['f1_1']:6.2f} {g[0]:15.2f} {g[1]:6.2f} "
                f"{g[2]:13.2f} {r['no_groups_floor']:10.2f}"
            )
            print(f"  {rule} one set (chosen without it): {one['params']}")
    print(f"default (best on all three): {results['default']}")


def evaluate_live(hold_s: float, root: Path = SHARED) -> dict[str, Any]:
    """The shipped defaults through the live service, beside the same through the core
    (people and the robot, as the service has them)."""
    from .groups_live import live

    out = {}
    for s in SEQUENCES:
        frames = load(s, root)
        found = live(frames, hold_s)
        core = run(frames, GroupParams())
        out[s] = {
            "live": {"f1_23": f1(frames, found, 2 / 3), "f1_1": f1(frames, found, 1.0)},
            "core": {"f1_23": f1(frames, core, 2 / 3), "f1_1": f1(frames, core, 1.0)},
            "hold_s": hold_s,
        }
    return out


def print_live(live: dict[str, Any]) -> None:
    print(f"\nthe shipped defaults (in-sample: chosen on all three), {'live':>14} {'core':>10}")
    for s, r in live.items():
        print(
            f"{s:18} F1 2/3 {r['live']['f1_23']:5.2f} (1: {r['live']['f1_1']:4.2f})"
            f"   {r['core']['f1_23']:5.2f} (1: {r['core']['f1_1']:4.2f})"
        )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="write the results as JSON")
    parser.add_argument(
        "--live", action="store_true", help="also feed the live service (1 s per frame)"
    )
    parser.add_argument("--hold-s", type=float, default=1.0, help="--live: each frame held")
    args = parser.parse_args(argv)
    if not 0.1 <= args.hold_s <= 10:
        parser.error(f"--hold-s must be in [0.1, 10] s, got {args.hold_s}")
    results = evaluate()
    print_results(results)
    if args.live:
        results["live"] = evaluate_live(args.hold_s)
        print_live(results["live"])
    if args.out is not None:
        args.out.write_text(json.dumps(results, indent=2) + "\n")


if __name__ == "__main__":
    main()
