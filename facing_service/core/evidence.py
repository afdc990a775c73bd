"""Soft evidence that accumulates: no angle gate decides alone.

Pure; the clock is the caller's (seconds). Each pose votes ``v = 2 * score - 1`` in
[-1, 1] from the facing score (``engagement.facing_score``: 1 inside the cone, falling
linearly with the angle beyond it and with the distance past ``near_m``): +1 inside the
cone, 0 half-way down its fall-off, -1 past it, where hri_engagement's rule votes only
-1 or +1. The votes accumulate over time, ``E += v * dt``, held within [0, ``memory_s``]:
``memory_s`` is the one length the machine adds (seconds of full evidence it remembers,
where the rule keeps a 10 s window). Its share, ``E / memory_s``, moves the level by the
rule's own thresholds (``rule.next_level`` on ``2 * share - 1``, the share's place on the
rule's mean vote), on every pose.

So a face inside the cone engages in ``0.75 * memory_s``; one a few degrees outside it
more slowly, as long as it keeps looking that way (its votes are small but positive);
one past the middle of the fall-off never; a glance adds a little and is forgotten. A gap
between poses counts at most ``MAX_GAP_S`` (silence is no evidence).
"""

from __future__ import annotations

from ..contract.levels import Level
from .rule import next_level

#: The longest gap between two poses that counts as evidence (seconds).
MAX_GAP_S = 0.5


def vote(score: float) -> float:
    """A pose's graded vote in [-1, 1] from its facing score in [0, 1]."""
    return 2.0 * score - 1.0


def accumulate(evidence: float, v: float, dt: float, memory_s: float) -> float:
    """The evidence after ``dt`` seconds of vote ``v``, within [0, memory_s]."""
    return min(memory_s, max(0.0, evidence + v * min(dt, MAX_GAP_S)))


def level(before: Level, evidence: float, memory_s: float) -> Level:
    """The level the evidence makes: the rule's machine on its share (the first pose
    makes a person DISENGAGED at once, where the rule waits for half its window)."""
    return next_level(before, 2.0 * evidence / memory_s - 1.0)
