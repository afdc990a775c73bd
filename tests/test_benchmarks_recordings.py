"""Engagement on the shared real recordings, through the real path (bag -> replay ->
router -> service), against hri_engagement's rule. The full table is
`python -m benchmarks.engagement.recordings` (README, On a ROS 2 robot)."""

from __future__ import annotations

import json

import pytest

from benchmarks.engagement.recordings import (
    REFERENCE_FIGURES,
    evaluate,
    first_folder_summary,
    print_table,
)

# processes, recordings or seconds-long scenarios; they read ../shared/data
pytestmark = [pytest.mark.slow, pytest.mark.figures, pytest.mark.shared_data]


@pytest.fixture(scope="module")
def results():
    # quick: 4x the recorded pace; the rule's mode, a second replay of every recording, is
    # held to the rule on the committed full run (test_benchmarks_crossval.py)
    outcome = evaluate(rate=4.0, rule_mode=False)
    print_table(outcome)
    return outcome


def test_the_rule_is_reproduced_faithfully(results):
    """The re-implementation gives the figures hri_engagement itself gave on the first
    shared folder (measured outside the project): the comparison is fair."""
    rule = first_folder_summary(results, "rule")
    assert rule["level"] == pytest.approx(REFERENCE_FIGURES["level"], abs=0.01)
    assert rule["engaged_or_not"] == pytest.approx(REFERENCE_FIGURES["engaged_or_not"], abs=0.01)
    assert rule["final"] == REFERENCE_FIGURES["final"]
    assert rule["first_engaged_s"] == REFERENCE_FIGURES["first_engaged_s"]


def test_the_service_beats_the_rule(results):
    """On both folders, without the ceiling row: the costlier error within the
    bounds (5 % on average, 15 % for the worst person), more often right, and ENGAGED in
    half the rule's delay. ENGAGING comes no later than ENGAGED (2.2 s median with the
    20-degree cone, not the 1.5 s asked for: docs/engagement.md says why)."""
    ours = results["service"]["summary"]["without_ceiling"]
    rule = results["rule"]["summary"]["without_ceiling"]
    assert ours["false_engaged"] <= 0.05, ours
    assert ours["false_engaged_worst"] <= 0.15, ours
    assert ours["first_engaging_s"] is not None, ours
    assert ours["level"] > rule["level"], (ours, rule)
    assert ours["engaged_or_not"] > rule["engaged_or_not"], (ours, rule)
    assert ours["final"] > rule["final"], (ours, rule)
    assert ours["first_engaged_s"] is not None, (
        f"the service never engaged most of the engaged people: {results['service']['rows']}"
    )
    assert ours["first_engaged_s"] * 2 <= rule["first_engaged_s"], (ours, rule)
    assert ours["first_engaging_s"] <= ours["first_engaged_s"], ours


def test_a_quick_run_leaves_the_committed_results_alone(results, monkeypatch, tmp_path):
    """`python -m benchmarks.engagement.recordings --quick` (the docs' reproduction) must
    not rewrite the tracked results/recordings.json, which holds the full run's figures."""
    from benchmarks.engagement import crossval, recordings

    monkeypatch.setattr(recordings, "evaluate", lambda *_args: results)
    monkeypatch.setattr(crossval, "evaluate", lambda *_args: {})
    monkeypatch.setattr(crossval, "print_results", lambda _results: None)
    committed = recordings.RESULTS.read_bytes()
    recordings.main(["--quick"])
    assert recordings.RESULTS.read_bytes() == committed
    out = tmp_path / "quick.json"
    recordings.main(["--quick", "--out", str(out)])
    assert json.loads(out.read_text())["rate"] == 4.0


def test_a_folder_without_labels_is_refused_in_one_line(tmp_path, capsys):
    from benchmarks.engagement import recordings

    with pytest.raises(SystemExit):
        recordings.main(["--bags", str(tmp_path)])
    assert f"--bags: {tmp_path} has no labels.json" in capsys.readouterr().err
