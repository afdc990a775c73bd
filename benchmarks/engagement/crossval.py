"""Engagement parameters chosen by cross-validation, by person first.

    python -m benchmarks.engagement.crossval  # every idea: in-sample and cross-validated

A robot meets new people: a rule chosen on the people it is judged on says little. Each
idea (``FAMILIES``: the head parameters it searches, the rest at their defaults, sustained
attention off unless searched: ``BEFORE``) picks its
candidate on the training person-recordings by a criterion (``criteria``) and is scored on
the held-out ones:
- **by person** (the main figures): leave one person out, five folds;
- **by recording** beside it: leave one recording out, ten folds.
In-sample figures (chosen on all, scored on all) are printed beside them to show how much
was fit. Every figure has a 95 % bootstrap interval over person-recordings
(``scoring``), and the two errors are counted apart.

The shipped rule (``preferred``): ideas are taken from the simplest (fewest parameters);
a more complex one replaces the incumbent only when its by-person cross-validated
advantage (level + ENGAGED-or-not, per person-recording, paired) has a bootstrap
interval above 0. Otherwise the simpler rule stays. The ceiling row (``scoring.CEILING``)
is left out of choices and targets, and printed.

Offline, so thousands of candidate runs take a minute: each recording goes once through
the service's own ROS 2 adapter (``ros2_input.route`` into ``People``, as the worker does
it), in receive order; then, per candidate, the person subjects' poses and losses go
through the tracker a service with those settings runs (``config.profiles.tracker_for``), on the
recording's clock. ``test_benchmarks_crossval`` checks that this gives the real path's
figures for the shipped defaults, and that the defaults are what this procedure picks.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from facing_service.config.settings import Settings

from .. import results_file
from . import scoring
from .criteria import Key, Rank, criteria, shortfall
from .families import BASE, FAMILIES, candidates, grid_of, setup
from .replayed import Recording, load, rows
from .rule_path import rule_timelines
from .scoring import FOLDERS, Row, advantage, summaries, summary


def folds(keys: Sequence[tuple[str, str]], by: str) -> dict[str, set[tuple[str, str]]]:
    """The held-out (recording, person) pairs of each fold: one per person, or recording."""
    out: dict[str, set[tuple[str, str]]] = {}
    for recording, person in keys:
        out.setdefault(person if by == "person" else recording, set()).add((recording, person))
    return dict(sorted(out.items()))


@dataclass
class Judged:
    family: str
    criterion: str
    parameters: int
    candidates: int
    in_sample: dict[str, Any]
    in_sample_choice: dict[str, Any]  # what the family picks on every person-recording
    by_person: dict[str, Any]  # cross-validated, leaving one person out
    by_recording: dict[str, Any]  # cross-validated, leaving one recording out
    folds: list[dict[str, Any]]  # per held-out person: the choice and its rows' summary
    rows: list[dict[str, Any]]  # the by-person held-out rows, in the recordings' order


Candidate = tuple[tuple[str, Any], ...]  # a candidate's settings, sorted: a dict key
_RECORDINGS: list[Recording] = []  # a worker's copy, set once by _worker_start


def _worker_start(recordings: list[Recording]) -> None:
    _RECORDINGS[:] = recordings


def _score(candidate: Candidate) -> list[Row]:
    """Every person-recording, in order, under one candidate's settings."""
    settings, research = setup(dict(candidate))
    return [row for r in _RECORDINGS for row in rows(r, settings, research)]


def score_all(
    options: Sequence[Candidate], recordings: list[Recording]
) -> dict[Candidate, list[Row]]:
    """Every candidate on every recording, on every core: thousands of runs of the
    tracker, each independent of the others. Spawned workers (a fork after a zenoh
    session opened in the same process would hang), each given the recordings once."""
    unique = list(dict.fromkeys(options))
    workers = min(os.cpu_count() or 1, 8)
    if workers < 2:
        _worker_start(recordings)
        return {c: _score(c) for c in unique}
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(workers, context, _worker_start, (recordings,)) as pool:
        return dict(zip(unique, pool.map(_score, unique, chunksize=8), strict=True))


def judge(
    family: str,
    grid: Mapping[str, Sequence[Any]],
    scored: Mapping[Candidate, list[Row]],
    ranks: Mapping[str, Rank],
) -> list[Judged]:
    """In-sample and cross-validated figures of one family, per criterion (``ranks``),
    from every candidate's rows (``score_all``)."""
    options = candidates(grid)
    table = [scored[tuple(sorted(candidate.items()))] for candidate in options]
    keys = [(row.recording, row.person) for row in table[0]]

    def best(train: set[tuple[str, str]], rank: Callable[[Sequence[Row]], tuple]) -> int:
        def on_train(option: int) -> tuple:
            return rank([row for row in table[option] if (row.recording, row.person) in train])

        return max(range(len(options)), key=on_train)

    scorable = {key for key in keys if key != scoring.CEILING}
    judged = []
    searched = sum(len(values) > 1 for values in grid.values())  # a fixed value is no choice
    for criterion, rank in ranks.items():
        held: dict[str, list[Row]] = {}
        fold_notes = []
        for by in ("person", "recording"):
            out: dict[tuple[str, str], Row] = {}
            for name, test in folds(keys, by).items():
                i = best(scorable - test, rank)
                mine = [row for row in table[i] if (row.recording, row.person) in test]
                out.update({(row.recording, row.person): row for row in mine})
                if by == "person":
                    fold_notes.append(
                        {"held_out": name, "choice": options[i], "summary": summary(mine, False)}
                    )
            held[by] = [out[key] for key in keys]
        chosen = best(scorable, rank)
        judged.append(
            Judged(
                family,
                criterion,
                searched,
                len(options),
                summaries(table[chosen]),
                options[chosen],
                summaries(held["person"]),
                summaries(held["recording"]),
                fold_notes,
                [asdict(row) for row in held["person"]],
            )
        )
    return judged


def _scored(j: Judged) -> list[Row]:
    return [row for row in map(lambda r: Row(**r), j.rows) if not row.ceiling]


def careful(j: Judged) -> bool:
    """By person, the costlier error within its targets: a DISENGAGED person called ENGAGED
    at most ``TARGETS["false_engaged"]`` of their time on average, and the worst
    person-recording within ``TARGETS["false_engaged_worst"]``."""
    cv = j.by_person["without_ceiling"]
    return (
        cv["false_engaged"] <= scoring.TARGETS["false_engaged"]
        and cv["false_engaged_worst"] <= scoring.TARGETS["false_engaged_worst"]
    )


def safe(j: Judged, rule: Mapping[Key, float]) -> bool:
    """By person, both errors within bounds for every person: a DISENGAGED person called
    ENGAGED at most ``TARGETS["false_engaged"]`` of their time on average and the worst
    person-recording within the target for the worst (the costlier error: the robot
    interrupts someone), and no person-recording more than ``BELOW_RULE`` below
    hri_engagement's rule on its row (the robot misses someone the rule would greet)."""
    return careful(j) and shortfall(_scored(j), rule) == 0.0


def preferred(
    judged: Sequence[Judged], rule: Mapping[Key, float]
) -> tuple[Judged, list[dict[str, Any]]]:
    """The issue's rule, both errors for every person first: only ideas whose by-person
    figures are ``safe`` compete, when any is; when none is, those that keep the costlier
    error within its targets (``careful``), when any does; from the simplest of those up,
    a more complex one replaces the incumbent only when its by-person cross-validated
    advantage is above its interval (paired bootstrap over person-recordings); the steps
    taken and refused, with their intervals."""
    eligible = (
        [j for j in judged if safe(j, rule)] or [j for j in judged if careful(j)] or list(judged)
    )
    order = sorted(eligible, key=lambda j: (j.parameters, j.candidates))
    incumbent, steps = order[0], []
    for challenger in order[1:]:
        mean, lo, hi = advantage(_scored(challenger), _scored(incumbent))
        steps.append(
            {
                "challenger": f"{challenger.family}, {challenger.criterion}",
                "incumbent": f"{incumbent.family}, {incumbent.criterion}",
                "advantage": mean,
                "ci": [lo, hi],
                "replaces": lo > 0,
            }
        )
        if lo > 0:
            incumbent = challenger
    return incumbent, steps


def shipped(recordings: Sequence[Recording]) -> dict[str, Any]:
    """The shipped defaults, in-sample (what the real path's committed run must match)."""
    defaults = Settings(**BASE)
    return summaries([row for r in recordings for row in rows(r, defaults)])


def rule_rows(folders: Sequence[Path] = FOLDERS) -> list[Row]:
    """hri_engagement's rule on every person-recording (``rule_path.rule_timelines``):
    the anchor each row is held to."""
    out = []
    for recording in scoring.labelled(folders):
        timelines = rule_timelines(recording.path, list(recording.persons))
        for person in recording.persons:
            out.append(scoring.score(recording.name, person, recording.label, timelines[person]))
    return out


def evaluate(folders: Sequence[Path] = FOLDERS) -> dict[str, Any]:
    recordings = load(folders)
    rule = {(r.recording, r.person): r.engaged_or_not for r in rule_rows(folders)}
    every = [tuple(sorted(c.items())) for name in FAMILIES for c in candidates(grid_of(name))]
    scored = score_all(every, recordings)
    ranks = criteria(rule)
    judged = [j for name in FAMILIES for j in judge(name, grid_of(name), scored, ranks)]
    best, steps = preferred(judged, rule)
    return {
        "shipped_defaults": shipped(recordings),
        "rule": [{"recording": k[0], "person": k[1], "engaged_or_not": v} for k, v in rule.items()],
        "judged": [asdict(j) for j in judged],
        "preferred": asdict(best),
        "steps": steps,
    }


def rule_of(results: Mapping[str, Any]) -> dict[Key, float]:
    """The rule's ENGAGED-or-not per row, as ``evaluate`` wrote it."""
    return {(r["recording"], r["person"]): r["engaged_or_not"] for r in results["rule"]}


def print_results(results: Mapping[str, Any]) -> None:
    line = scoring.figures_line
    print("Without the ceiling row (targets); intervals: 95 % bootstrap over person-recordings")
    print(f"shipped defaults, in-sample: {line(results['shipped_defaults']['without_ceiling'])}\n")
    for j in results["judged"]:
        print(
            f"{j['family']} ({j['parameters']} parameters, {j['candidates']} candidates), "
            f"chosen {j['criterion']}: {j['in_sample_choice']}"
        )
        print(f"  in-sample     {line(j['in_sample']['without_ceiling'])}")
        print(f"  by person     {line(j['by_person']['without_ceiling'])}")
        print(f"  by recording  {line(j['by_recording']['without_ceiling'])}")
    print("\nFrom the simplest up, a challenger replaces the incumbent only above its interval:")
    for s in results["steps"]:
        verdict = "replaces it" if s["replaces"] else "kept out"
        print(
            f"  {s['challenger']:52} vs {s['incumbent']:40} "
            f"{s['advantage']:+.3f} [{s['ci'][0]:+.3f}, {s['ci'][1]:+.3f}] {verdict}"
        )
    best = results["preferred"]
    print(f"\npreferred: {best['family']}, chosen {best['criterion']}: {best['in_sample_choice']}")
    print(f"  by person, without the ceiling: {line(best['by_person']['without_ceiling'])}")
    print(f"  by person, with it:             {line(best['by_person']['all'])}")
    print(f"  by recording, without it:       {line(best['by_recording']['without_ceiling'])}")
    print(f"  {'held out':31} {scoring.ROW_HEAD}")
    for row in best["rows"]:
        print(f"  {scoring.row_name(row):31} {scoring.row_cells(row)}")
    for fold in best["folds"]:
        print(f"  person {fold['held_out']}: chosen without them {fold['choice']}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--bags", type=Path, nargs="+", default=list(FOLDERS), help="folders of labelled bags"
    )
    parser.add_argument("--out", type=Path, default=None, help="write the results as JSON")
    args = parser.parse_args(argv)
    results = evaluate(args.bags)
    print_results(results)
    if args.out is not None:
        results_file.write(
            args.out, results, "python -m benchmarks.engagement.crossval", vars(args)
        )
        print(f"written to {args.out}")


if __name__ == "__main__":
    main()
