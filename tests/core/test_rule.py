"""hri_engagement 2.0.1's rule (core.rule): its vote window and level machine as its node
runs them, and the ticks counted on the poses' clock."""

from __future__ import annotations

from facing_service.contract.levels import Level
from facing_service.core.rule import RuleParams, Votes, next_level, step, tick

P = RuleParams()  # 10 Hz, 10 s: 100 votes, a level from 50


def levels_of(votes: list[int | None]) -> list[Level]:
    state, seen = Votes(), []
    for vote in votes:
        state = tick(state, vote, P)
        seen.append(state.level)
    return seen


def test_no_level_until_half_the_window_then_slow_by_design():
    levels = levels_of([-1] * 50 + [1] * 100)
    assert levels[48] is Level.UNKNOWN and levels[49] is Level.DISENGAGED  # half a window
    # ENGAGING once the mean passes -0.4 (30 % of the votes +1), ENGAGED past 0.5 (75 %)
    assert levels.index(Level.ENGAGING) == 50 + 21  # 22 votes +1 of 72: mean -0.39
    assert levels.index(Level.ENGAGED) - 50 >= 40  # more than 4 s of facing to be ENGAGED


def test_the_level_moves_one_step_a_tick_on_the_windows_mean():
    assert next_level(Level.UNKNOWN, 1.0) is Level.DISENGAGED  # never straight to ENGAGED
    assert next_level(Level.DISENGAGED, -0.4) is Level.DISENGAGED  # strictly above -0.4
    assert next_level(Level.DISENGAGED, -0.39) is Level.ENGAGING
    assert next_level(Level.ENGAGING, 0.5) is Level.ENGAGING
    assert next_level(Level.ENGAGING, 0.51) is Level.ENGAGED
    assert next_level(Level.ENGAGING, -0.61) is Level.DISENGAGED
    assert next_level(Level.ENGAGED, 0.39) is Level.DISENGAGING
    assert next_level(Level.DISENGAGING, 0.61) is Level.ENGAGED
    assert next_level(Level.DISENGAGING, -0.51) is Level.DISENGAGED
    assert next_level(Level.DISENGAGING, 0.0) is Level.DISENGAGING


def test_a_tick_without_a_face_is_no_vote_and_the_window_keeps_its_size():
    state = Votes()
    for _ in range(150):
        state = tick(state, 1, P)
    assert len(state.votes) == 100 and state.level is Level.ENGAGED
    assert tick(state, None, P).votes == state.votes


def test_poses_vote_for_the_ticks_they_were_the_latest():
    """A pose at 30 Hz: each 0.1 s tick votes as the pose that was latest at it; a pose's
    own vote waits for the next tick; a silence of 1 s is ten ticks of the last vote."""
    state = Votes()
    for i in range(31):  # 1 s of poses voting engaged, then one voting not
        state = step(state, i / 30, True, P)
    assert state.votes == (1,) * 10 and state.vote == 1
    state = step(state, 31 / 30, False, P)
    assert state.votes == (1,) * 10 and state.vote == -1  # the tick at 1.1 s is still to come
    state = step(state, 2.05, True, P)  # silent until 2.05 s: ticks 1.1 .. 2.0 vote -1
    assert state.votes == (1,) * 10 + (-1,) * 10


def test_a_silence_longer_than_the_window_counts_one_window():
    state = step(step(Votes(), 0.0, True, P), 0.05, True, P)
    state = step(state, 3600.0, False, P)
    assert len(state.votes) == 100 and set(state.votes) == {1}
