"""hri_engagement's rule (ROS4HRI hri_engagement 2.0.1, ``engagement_node.py``): what
robots run today, as a mode of the service (``--engagement rule``) and the anchor the
evaluation holds the service's own machines to (benchmarks: one code).

Pure; the clock is the caller's (the poses' stamps, seconds). Every ``1/rate_hz`` a tracked
person with a face votes +1 when their visual social engagement (``mutual_gaze.score``)
is above the threshold, -1 otherwise (beyond ``max_distance_m`` too); a tick with no
face is no vote. The level moves on the mean of the last ``window_s`` of votes, once half
the window is filled (until then UNKNOWN, as hri_engagement says), one step a tick:

    UNKNOWN -> DISENGAGED                     at the first mean
    DISENGAGED -> ENGAGING                    mean > -0.4
    ENGAGING -> ENGAGED / DISENGAGED          mean > 0.5 / < -0.6
    ENGAGED -> DISENGAGING                    mean < 0.4
    DISENGAGING -> ENGAGED / DISENGAGED       mean > 0.6 / < -0.5

hri_engagement votes on a timer from the latest transform; here the timer's ticks are
counted on the poses' clock: when a pose comes, each tick since the previous one votes as
the previous pose did (it was the latest then; at most a window of them), and its own
vote waits for the ticks to come.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..contract.levels import Level


@dataclass(frozen=True, slots=True)
class RuleParams:
    """The vote window's parameters (hri_engagement 2.0.1's defaults)."""

    rate_hz: float = 10.0  # its timer
    window_s: float = 10.0  # observation_window

    @property
    def size(self) -> int:
        return int(self.rate_hz * self.window_s)

    @property
    def min_votes(self) -> int:
        return int(0.5 * self.size)


@dataclass(frozen=True, slots=True)
class Votes:
    """One person's votes (+1/-1, oldest first, at most a window), the level they made,
    and the tick of the latest pose (``None`` before the first)."""

    level: Level = Level.UNKNOWN
    votes: tuple[int, ...] = ()
    tick: int | None = None
    vote: int = -1  # the latest pose's vote, cast by the ticks while it stays the latest


def next_level(level: Level, mean: float) -> Level:
    """One tick of hri_engagement's level machine on the window's mean vote."""
    if level is Level.UNKNOWN:
        return Level.DISENGAGED
    if level is Level.DISENGAGED and mean > -0.4:
        return Level.ENGAGING
    if level is Level.ENGAGING:
        if mean < -0.6:
            return Level.DISENGAGED
        if mean > 0.5:
            return Level.ENGAGED
    if level is Level.ENGAGED and mean < 0.4:
        return Level.DISENGAGING
    if level is Level.DISENGAGING:
        if mean > 0.6:
            return Level.ENGAGED
        if mean < -0.5:
            return Level.DISENGAGED
    return level


def tick(state: Votes, vote: int | None, p: RuleParams) -> Votes:
    """One tick of the timer: a vote (None: the tick saw no face), then the level."""
    votes = state.votes if vote is None else (*state.votes[-(p.size - 1) :], vote)
    level = state.level
    if len(votes) >= p.min_votes:
        level = next_level(level, sum(votes) / len(votes))
    return Votes(level, votes, state.tick, state.vote)


def step(state: Votes, t: float, engaged: bool, p: RuleParams) -> Votes:
    """Fold one pose at time ``t`` (seconds) voting ``engaged``. The ticks since the
    previous pose vote as that pose did (it was the latest at each of them); this pose's
    vote is the latest from now on, counted by the ticks to come."""
    now = math.floor(t * p.rate_hz)
    if state.tick is not None:
        for _ in range(min(now - state.tick, p.size)):
            state = tick(state, state.vote, p)
    return Votes(state.level, state.votes, max(now, state.tick or now), 1 if engaged else -1)
