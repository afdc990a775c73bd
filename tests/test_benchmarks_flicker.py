"""A face's facing decision held steady on the shared recordings (``python -m
benchmarks.engagement.flicker``): the shipped window is the one chosen on them, it cuts
the flips without adding more than 0.5 s to a turn toward the robot, and the committed
figures are this run's."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from benchmarks.engagement.flicker import RESULTS, TARGET_DELAY_S, evaluate, name
from facing_service.config.settings import Settings

pytestmark = [pytest.mark.slow, pytest.mark.figures, pytest.mark.shared_data]


@pytest.fixture(scope="module")
def results():
    return evaluate()


def test_the_shipped_window_is_the_one_chosen_on_the_recordings(results):
    assert results["chosen_on_all"] == Settings().head_facing_window_s


def test_it_cuts_the_flips_and_says_a_turn_toward_the_robot_within_half_a_second(results):
    shipped = name(Settings().head_facing_window_s)
    figures = results["windows"][shipped]
    before = results["windows"][name(0.0)]
    assert figures["flips_per_min_mean"] * 4 <= before["flips_per_min_mean"]
    assert figures["toward"]["max_s"] <= TARGET_DELAY_S
    for row in results["rows"]:  # no one flips more than pose by pose
        assert row[shipped] <= row[name(0.0)], row


def test_the_committed_figures_are_this_runs(results):
    committed = json.loads(Path(RESULTS).read_text())
    assert committed["rows"] == results["rows"]
    assert committed["chosen_on_all"] == results["chosen_on_all"]
