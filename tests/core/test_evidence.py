"""Soft evidence that accumulates (core.evidence): the facing score as a graded
vote, summed within a memory, levels by hri_engagement's own thresholds on its share."""

from __future__ import annotations

from facing_service.contract.levels import Level
from facing_service.core.evidence import MAX_GAP_S, accumulate, level, vote

MEMORY = 2.0


def run(score: float, seconds: float, start: float = 0.0, before=Level.DISENGAGED, dt=1 / 30):
    """The levels a face scoring ``score`` passes through, each with when it came."""
    held, now, seen = start, 0.0, [(0.0, before)]
    for _ in range(round(seconds / dt)):
        now += dt
        held = accumulate(held, vote(score), dt, MEMORY)
        if (new := level(seen[-1][1], held, MEMORY)) is not seen[-1][1]:
            seen.append((now, new))
    return held, seen


def test_votes_are_graded_from_minus_one_to_one():
    assert vote(1.0) == 1.0 and vote(0.5) == 0.0 and vote(0.0) == -1.0
    assert vote(0.6) > 0 > vote(0.4)


def test_a_face_in_the_cone_engages_in_three_quarters_of_the_memory():
    _, seen = run(1.0, 3.0)
    assert [lv for _, lv in seen] == [Level.DISENGAGED, Level.ENGAGING, Level.ENGAGED]
    assert 0.55 < seen[1][0] < 0.7  # share above 0.3: 0.6 s
    assert 1.45 < seen[2][0] < 1.6  # share above 0.75: 1.5 s


def test_a_face_a_little_outside_engages_if_it_keeps_looking_and_one_past_never():
    _, slow = run(0.6, 20.0)  # a vote of +0.2: five times slower
    assert slow[-1][1] is Level.ENGAGED and 7.0 < slow[-1][0] < 8.0
    _, never = run(0.45, 60.0)  # votes just below 0: no evidence builds
    assert [lv for _, lv in never] == [Level.DISENGAGED]


def test_a_glance_is_forgotten_and_turning_away_disengages():
    held, seen = run(1.0, 0.5)  # half a second toward the robot
    assert seen[-1][1] is Level.DISENGAGED and abs(held - 0.5) < 1e-9
    held, seen = run(0.0, 1.0, start=held, before=seen[-1][1])
    assert held == 0.0 and seen[-1][1] is Level.DISENGAGED
    engaged, _ = run(1.0, 5.0)  # held at the memory, then away: DISENGAGING, DISENGAGED
    _, away = run(0.0, 3.0, start=engaged, before=Level.ENGAGED)
    assert [lv for _, lv in away] == [Level.ENGAGED, Level.DISENGAGING, Level.DISENGAGED]
    assert away[1][0] < 0.7 and away[2][0] < 1.6


def test_the_evidence_stays_within_its_memory_and_a_gap_counts_little():
    assert accumulate(1.9, 1.0, 1.0, MEMORY) == MEMORY
    assert accumulate(0.1, -1.0, 1.0, MEMORY) == 0.0
    assert accumulate(0.0, 1.0, 10.0, MEMORY) == MAX_GAP_S  # silence is no evidence
