"""Where to stand, judged on where people stood (benchmarks/groups/join.py): the
baselines do what they say, the shipped parameters are the ones chosen, the page's table
is the committed results', and a fresh run on the shared sequences still holds them."""

from __future__ import annotations

import json
import math
from dataclasses import asdict

import numpy as np
import pytest

from benchmarks.groups import join
from facing_service.core.social.join import JoinParams


def square_missing_one() -> join.Case:
    """Four people on a 0.8 m circle around (3, 0), the one at 180° left out."""
    angles = [0.0, math.pi / 2, 3 * math.pi / 2]
    members = np.array([(3 + 0.8 * math.cos(a), 0.8 * math.sin(a)) for a in angles])
    headings = np.array([a + math.pi for a in angles])
    return join.Case(members, headings, np.zeros((0, 2)), np.array([2.2, 0.0]), 0.0)


def test_the_baselines_are_what_the_issue_says():
    case = square_missing_one()
    x, y, _ = join.centroid(case)
    assert (x, y) == pytest.approx(((3.8 + 3.0 + 3.0) / 3, 0.0))
    sx, sy, yaw = join.naive_slot(case)
    radius = np.hypot(*(case.members - [x, y]).T).mean()
    assert (sx, sy) == pytest.approx((x - radius, 0.0), abs=1e-9)  # the largest gap's middle
    assert yaw == pytest.approx(math.atan2(y - sy, x - sx))  # facing the centroid


def test_the_shipped_parameters_are_the_ones_chosen_and_the_page_is_the_results():
    chosen = json.loads(join.RESULTS.read_text())["chosen_on_all"]
    assert chosen == json.loads(json.dumps(asdict(JoinParams())))
    assert join.main(["--page", "--check"]) == 0, (
        "regenerate: python -m benchmarks.groups.join --page"
    )


@pytest.mark.slow
@pytest.mark.figures
@pytest.mark.shared_data
def test_a_fresh_run_holds_the_committed_figures():
    """About a minute: every case of the six sequences, every candidate, the robot at ten
    places. A place for at least 80 % of every sequence's cases; below both baselines but
    on GDet (whose headings do not tell a pair's two sides apart: docs/groups.md); where
    the robot stands moves no place of a group with one clear gap, and the median less
    than the first rule did; the committed figures reproduced."""
    fresh = join.evaluate()
    committed = json.loads(join.RESULTS.read_text())
    for sequence, row in fresh["sequences"].items():
        assert row["join"]["found"] >= join.FOUND_AT_LEAST, (sequence, row)
        assert row["join"]["median_m"] == pytest.approx(
            committed["sequences"][sequence]["join"]["median_m"], abs=1e-9
        )
    for sequence in ("SALSA/CocktailParty", "Synth", "CoffeeBreak/Seq1", "CoffeeBreak/Seq2"):
        row = fresh["sequences"][sequence]
        baselines = min(row["centroid"]["median_m"], row["naive_slot"]["median_m"])
        assert row["join"]["median_m"] < baselines, (sequence, row)
    for sequence, row in fresh["sequences"].items():  # the group's place, not the
        assert row["join"]["one_gap_robot_spread_m"] <= 0.1, (sequence, row)  # robot's
        assert row["join"]["robot_spread_m"] <= row["before"]["robot_spread_m"], (sequence, row)


@pytest.mark.slow
@pytest.mark.shared_data
def test_the_scene_replayed_gives_the_live_services_places_case_for_case():
    """The join's figures over every case come from the service's scene alone
    (``--replayed``): it must say what the live service says. Twelve cases of CoffeeBreak
    Seq1 (some given a place, some not) through both, the robot 3 m from the members,
    each held 1.5 s: the benchmark's 0.6 s put one of its 600 live answers past a group's
    being said (a loaded machine's timing, not a place worked out otherwise)."""
    from benchmarks.groups.join_live import LIVE_ROBOTS, RENAME, _distance, _placed, live_cases
    from benchmarks.groups.live import live_said
    from benchmarks.groups.replay import said_with_places
    from benchmarks.groups.sequences import load

    picked = live_cases(load("CoffeeBreak/Seq1"), 12)
    shifted = [c.members.mean(axis=0) + np.array(LIVE_ROBOTS[0]) for _, _, c, _ in picked]
    frames = [_placed(shown, at, k) for k, ((_, shown, _, _), at) in
              enumerate(zip(picked, shifted, strict=True))]  # fmt: skip

    def places(said: list[list[dict]]) -> list[dict]:
        return [{tuple(g["members"]): g["join"] and (round(g["join"]["x"], 6),
                 round(g["join"]["y"], 6)) for g in groups} for groups in said]  # fmt: skip

    replayed = said_with_places(frames, 1.5)
    distances = [_distance(groups, case, rest, at, RENAME * k) for k, (groups, (_, _, case, rest),
                 at) in enumerate(zip(replayed, picked, shifted, strict=True))]  # fmt: skip
    assert None in distances and any(d is not None for d in distances), distances
    assert places(live_said(frames, 1.5)) == places(replayed)


def test_the_joins_bound_page_is_the_results_and_no_cost_per_group_meets_both_targets():
    """The committed bound (benchmarks/groups/join_bound.py): the page is its table, and
    what the page concludes from it holds in it: no cost per group of the shipped set
    both keeps every sequence's F1 at GCFF's one set or above and holds the remaining
    members together in 80 % of every sequence's cases with the member absent."""
    from benchmarks.groups import join_bound

    assert join_bound.main(["--page", "--check"]) == 0, (
        "regenerate: python -m benchmarks.groups.join_bound --page"
    )
    results = json.loads(join_bound.RESULTS.read_text())
    for cost in (f"{c:g}" for c in results["costs"]):
        assert not all(
            r["costs"][cost]["f1"] >= r["gcff_one_set_f1"]
            and r["costs"][cost]["absent"]["share"] >= join_bound.TARGET
            for r in results["sequences"].values()
        ), cost


@pytest.mark.shared_data
def test_a_fresh_run_of_the_joins_bound_gives_the_committed_figures():
    """CoffeeBreak Seq1 (a few seconds) measured again: every figure as committed, and no
    cost per group there both at GCFF's one set and holding 80 % of the pairs with the
    member absent (the shipped set's figures change with the grouping, and this with
    them)."""
    from benchmarks.groups import join_bound

    sequence = "CoffeeBreak/Seq1"
    fresh = json.loads(json.dumps(join_bound.evaluate(sequences=[sequence])))["sequences"]
    committed = json.loads(join_bound.RESULTS.read_text())["sequences"][sequence]
    assert fresh[sequence] == committed
    for row in committed["costs"].values():
        assert row["f1"] < committed["gcff_one_set_f1"] or row["absent"]["share"] < 0.8, row
