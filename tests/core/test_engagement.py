"""The facing score, zones and the engagement state machine (pure, on a fake clock)."""

from __future__ import annotations

import math
import random
from dataclasses import replace

import pytest

from facing_service.config.profiles import engagement_params, head_profile
from facing_service.config.settings import Settings
from facing_service.core.engagement import (
    Engagement,
    EngagementParams,
    Level,
    Zone,
    advance,
    facing_score,
    step,
    vote,
    zone,
)

P = engagement_params(Settings())  # the service's defaults


@pytest.mark.parametrize(
    ("angle", "distance", "score"),
    [
        (0.0, 1.0, 1.0),
        (20.0, 2.5, 1.0),
        (25.0, 1.0, 0.8),
        (45.0, 1.0, 0.0),
        (90.0, 1.0, 0.0),
        (0.0, 3.5, 0.5),
        (0.0, 4.5, 0.0),
        (30.0, 3.0, 0.6 * 0.75),
        (None, None, 0.0),
    ],
)
def test_facing_score(angle, distance, score):
    assert facing_score(angle, distance, P) == pytest.approx(score)


@pytest.mark.parametrize(
    ("distance", "expected"),
    [
        (0.3, Zone.INTIMATE),
        (0.45, Zone.PERSONAL),
        (1.0, Zone.PERSONAL),
        (1.2, Zone.SOCIAL),
        (3.59, Zone.SOCIAL),
        (3.6, Zone.PUBLIC),
        (None, Zone.INTIMATE),
    ],
)
def test_zones(distance, expected):
    assert zone(distance, P) is expected


def run(scores, dt=1 / 30, start=0.0, state=None):
    """Feed (score, or None for a dropped frame) every dt; the level changes with times."""
    state = state or Engagement()
    trace = []
    t = start
    for score in scores:
        t += dt
        previous = state.level
        state = advance(state, t, P) if score is None else step(state, t, score, P)
        if state.level is not previous:
            trace.append((round(t, 3), state.level))
    return state, trace


def test_first_sample_makes_a_body_disengaged_then_it_engages_within_a_second():
    _, trace = run([0.0] * 30 + [1.0] * 60)
    levels = [level for _, level in trace]
    assert levels == [Level.DISENGAGED, Level.ENGAGING, Level.ENGAGED]
    engaged_at = next(t for t, level in trace if level is Level.ENGAGED)
    assert 1.0 + 0.5 <= engaged_at <= 1.0 + 1.0  # the dwell, but within a second


def test_turning_away_disengages_within_one_and_a_half_seconds():
    state, _ = run([1.0] * 60)
    assert state.level is Level.ENGAGED
    state, trace = run([0.0] * 60, start=2.0, state=state)
    assert [level for _, level in trace] == [Level.DISENGAGING, Level.DISENGAGED]
    assert trace[-1][0] - 2.0 <= 1.5


def test_a_brief_glance_never_becomes_engaged():
    state, _ = run([0.0] * 30)
    state, trace = run([1.0] * 18 + [0.0] * 60, start=1.0, state=state)  # 0.6 s glance
    assert Level.ENGAGED not in [level for _, level in trace]
    assert state.level is Level.DISENGAGED


def test_looking_away_briefly_keeps_an_engaged_body_engaged():
    state, _ = run([1.0] * 60)
    state, trace = run([0.0] * 6 + [1.0] * 30, start=2.0, state=state)  # 0.2 s away
    assert all(level is Level.ENGAGED for _, level in trace)


def test_noise_around_facing_does_not_flicker():
    rng = random.Random(1)
    # squarely facing with 5 degrees of yaw noise at 1.5 m: the score barely moves
    scores = [facing_score(abs(rng.gauss(0, 5)), 1.5, P) for _ in range(30 * 60)]
    _, trace = run(scores)  # appears already facing: ENGAGING at once, then ENGAGED, then calm
    assert [level for _, level in trace] == [Level.ENGAGING, Level.ENGAGED]


def test_dropouts_hold_the_level_and_the_dwell_still_expires_between_samples():
    state, _ = run([1.0] * 60)
    state, trace = run([None] * 30, start=2.0, state=state)  # the tracker is silent 1 s
    assert state.level is Level.ENGAGED and trace == []
    state = step(state, 3.1, 0.0, P)  # one sample, looking away, after the gap:
    assert state.score < P.disengage_below  # the gap weighs as its length (dt-aware)
    assert state.level is Level.DISENGAGING
    state = advance(state, 3.1 + P.disengage_dwell_s, P)  # no more samples: dwell expires
    assert state.level is Level.DISENGAGED


def test_promotion_needs_a_fresh_observation():
    state, _ = run([1.0] * 12)  # ENGAGING, not yet ENGAGED
    assert state.level is Level.ENGAGING
    assert advance(state, state.last + 1.0, P).level is Level.ENGAGING  # silent: no promotion


HEAD = replace(head_profile(Settings()).engagement, steady_deg=5.0)  # steadiness on (research)


def looking(yaw_degs, params, dt=1 / 30):
    """A head whose robot direction turns through ``yaw_degs`` (one per frame, 1 m away),
    scored as the tracker scores a face: the levels it passes through."""
    state, seen = Engagement(), []
    for i, yaw in enumerate(yaw_degs):
        a = math.radians(yaw)
        direction = (math.cos(a), math.sin(a), 0.0)
        state = step(state, (i + 1) * dt, facing_score(abs(yaw), 1.0, params), params, direction)
        seen.append(state.level)
    return state, seen


def test_steadiness_is_off_unless_asked_for():
    assert head_profile(Settings()).engagement.steady_deg is None
    assert HEAD.steady_deg == 5.0


def test_a_head_held_still_in_the_cone_engages_with_steadiness_as_without():
    rng = random.Random(3)
    still = [10.0 + rng.gauss(0, 1.0) for _ in range(90)]  # 3 s, a degree of tracker jitter
    _, with_it = looking(still, HEAD)
    _, without = looking(still, replace(HEAD, steady_deg=None))
    assert with_it[-1] is Level.ENGAGED
    assert with_it.index(Level.ENGAGED) == without.index(Level.ENGAGED)


def test_a_head_sweeping_through_the_cone_never_engages_with_steadiness():
    """Looking around: the head turns at 30 deg/s between -40 and +40 deg, so it spends
    over a second at a time inside the cone. Without steadiness (nor sustained attention,
    which alone would keep this sweep out) that engages; with it, the head is always far
    from where it just was, and it never does."""
    sweep = [40.0 - abs((i * 1.0) % 160 - 80) for i in range(30 * 12)]
    _, without = looking(sweep, replace(HEAD, steady_deg=None, sustain_s=None))
    _, with_it = looking(sweep, replace(HEAD, sustain_s=None))
    assert Level.ENGAGED in without
    assert Level.ENGAGED not in with_it and Level.ENGAGING not in with_it


def test_two_speeds_engaging_at_once_engaged_only_after_sustained_attention():
    """ENGAGING is the quick signal, ENGAGED (what a robot greets on) needs the
    face in the cone for every sample of ``sustain_s``: a glance, or glances repeated with
    gaps between them, make a body ENGAGING and never ENGAGED; steady attention does."""
    two = replace(P, sustain_s=2.0, tau_s=0.25, engage_dwell_s=0.5)
    glances = ([1.0] * 45 + [0.0] * 6) * 4  # 1.5 s in the cone, 0.2 s out, four times
    trace = _trace(glances, two)
    assert Level.ENGAGING in trace and Level.ENGAGED not in trace
    steady = _trace([1.0] * 90, two)  # 3 s in the cone
    engaged_at = steady[Level.ENGAGED]
    assert steady[Level.ENGAGING] < 0.1 and engaged_at == pytest.approx(2.0 + 1 / 30, abs=0.04)
    # the same glances engage without sustain_s: ENGAGING held its dwell
    assert Level.ENGAGED in _trace(glances, replace(two, sustain_s=None))


def _trace(scores: list[float], p: EngagementParams, dt: float = 1 / 30) -> dict[Level, float]:
    """When each level was first reached, feeding ``scores`` every ``dt``."""
    state, first, t = Engagement(), {}, 0.0
    for score in scores:
        t += dt
        state = step(state, t, score, p)
        first.setdefault(state.level, t)
    return first


def _angles(angles_deg: list[float], p: EngagementParams, dt: float = 0.1) -> list[Level]:
    """The levels of a face seen at ``angles_deg`` from the robot (1 m away), every ``dt``,
    scored and voted as the tracker does."""
    state, seen = Engagement(), []
    for i, angle in enumerate(angles_deg):
        state = step(state, (i + 1) * dt, facing_score(angle, 1.0, p), p, None, vote(angle, 1.0, p))
        seen.append(state.level)
    return seen


#: The head's shipped parameters, with the soft vote at 36 degrees over 1.5 s.
VOTING = replace(head_profile(Settings()).engagement, vote_deg=36.0, vote_tau_s=1.5)


def test_the_soft_vote_engages_a_head_that_roams_around_the_cone():
    """An engaged person whose head roams in and out of the cone (here 16-32
    degrees, 24 the cone) was never ENGAGED by sustained attention alone; voting within a
    wider field, they are ENGAGED within a few seconds and stay so while they attend."""
    roaming = [24.0 + 8.0 * math.sin(i / 4.0) for i in range(150)]  # 15 s at 10 Hz
    without = _angles(roaming, replace(VOTING, vote_deg=None))
    assert Level.ENGAGED not in without[:60]  # not within 6 s
    levels = _angles(roaming, VOTING)
    first = levels.index(Level.ENGAGED)
    assert first <= 40  # within 4 s
    assert all(level is Level.ENGAGED for level in levels[first:])  # held while attending


def test_the_soft_vote_starts_from_nothing_and_a_glance_does_not_reach_it():
    """The share starts at 0: one vote, or a glance of a second, is no attention; looking
    away ends it (DISENGAGING, then DISENGAGED)."""
    glance = [70.0] * 20 + [10.0] * 10 + [70.0] * 40
    assert Level.ENGAGED not in _angles(glance, replace(VOTING, sustain_s=10.0))
    away = [30.0] * 60 + [80.0] * 40  # attends at 30 degrees (outside the cone), then leaves
    levels = _angles(away, replace(VOTING, sustain_s=10.0))
    assert Level.ENGAGED in levels[:60] and levels[-1] is Level.DISENGAGED


def test_the_soft_vote_is_off_unless_asked_for():
    assert P.vote_deg is None and vote(10.0, 1.0, P) == 0.0
    assert vote(35.0, 1.0, VOTING) == 1.0 and vote(37.0, 1.0, VOTING) == 0.0
    assert vote(10.0, 5.0, VOTING) == 0.0  # beyond far_m: no vote, as the rule's distance
    assert vote(None, None, VOTING) == 0.0
