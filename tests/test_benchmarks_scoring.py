"""How the recordings are scored: both error kinds apart, intervals that say how sure a
figure is, and a paired advantage that refuses a difference inside its noise."""

from __future__ import annotations

import json

import pytest

from benchmarks.engagement import scoring
from benchmarks.engagement.scoring import Row, advantage, score, summary
from facing_service.contract.levels import Level


def timeline(levels, dt=0.1):
    return [(round(i * dt, 3), level) for i, level in enumerate(levels)]


def test_a_disengaged_person_called_engaged_counts_as_false_engaged_not_missed():
    # 2 s warm-up, then 4 s ENGAGED and 4 s DISENGAGED
    levels = [Level.DISENGAGED] * 20 + [Level.ENGAGED] * 40 + [Level.DISENGAGED] * 40
    row = score("rec", "p", Level.DISENGAGED, timeline(levels))
    assert row.false_engaged == pytest.approx(0.5)
    assert row.missed is None
    assert row.level == pytest.approx(0.5) and row.final_ok
    assert row.first_engaged_s == 2.0
    # two changes after the warm-up, over 8 s
    assert row.changes_per_min == pytest.approx(2 / (7.9 / 60), abs=0.01)


def test_an_engaged_person_not_called_engaged_counts_as_missed():
    levels = [Level.DISENGAGED] * 30 + [Level.ENGAGING] * 10 + [Level.ENGAGED] * 60
    row = score("rec", "p", Level.ENGAGED, timeline(levels))
    assert row.missed == pytest.approx(20 / 80)
    assert row.false_engaged is None


def rows(values, label="DISENGAGED"):
    return [
        Row(f"r{i}", "p", label, v, v, 1 - v, None, True, None, 2, 1.0)
        for i, v in enumerate(values)
    ]


def test_the_interval_is_wide_for_few_scattered_rows_and_narrow_for_many_alike():
    scattered = summary(rows([0.2, 1.0, 0.6, 0.9]))
    alike = summary(rows([0.80, 0.82, 0.81, 0.79] * 10))
    lo, hi = scattered["level_ci"]
    assert lo <= scattered["level"] <= hi and hi - lo > 0.3
    lo, hi = alike["level_ci"]
    assert lo <= alike["level"] <= hi and hi - lo < 0.02


def test_an_advantage_inside_its_interval_is_not_an_advantage():
    base = rows([0.5, 0.9, 0.3, 0.8, 0.6])
    mixed = rows([0.6, 0.8, 0.4, 0.7, 0.7])  # better on three, worse on two
    mean, lo, hi = advantage(mixed, base)
    assert lo <= 0 <= hi and lo < mean < hi
    clearly = rows([0.7, 1.0, 0.5, 0.9, 0.8])  # better on every one
    mean, lo, hi = advantage(clearly, base)
    assert lo > 0


def test_the_ceiling_row_is_summarised_apart():
    ceiling = Row(*scoring.CEILING, "ENGAGED", 0.3, 0.3, None, 0.7, False, None, 3, 2.0)
    both = scoring.summaries([*rows([1.0, 1.0]), ceiling])
    assert both["all"]["of"] == 3 and both["without_ceiling"]["of"] == 2
    assert both["without_ceiling"]["missed"] is None


@pytest.mark.shared_data
def test_the_shared_folders_are_one_set_and_a_name_twice_is_refused(tmp_path):
    found = scoring.labelled()
    assert len(found) == 10
    assert sum(len(r.persons) for r in found) == 12
    assert {p for r in found for p in r.persons} == {"rorql", "aqfwx", "dndaq", "eloek", "ghfbv"}
    again = tmp_path / "again"
    again.mkdir()
    (again / "labels.json").write_text(
        json.dumps({"recordings": {"1p_AA_eng_1": {"persons": ["x"], "expected_level": 3}}})
    )
    with pytest.raises(ValueError, match="1p_AA_eng_1 is in both"):
        scoring.labelled([*scoring.FOLDERS, again])
