"""How an engagement idea picks its candidate on the training person-recordings
(``crossval``): higher is better, compared as tuples."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

from . import scoring
from .scoring import Row, summary


def on_average(scored: Sequence[Row]) -> tuple[float, ...]:
    """Higher is better: level + ENGAGED-or-not (means), then the sooner first ENGAGED."""
    s = summary(scored, intervals=False)
    first = s["first_engaged_s"]
    return (
        round(float(s["level"]) + float(s["engaged_or_not"]), 6),
        -(float(first) if first is not None else 1e9),
    )


def at_worst(scored: Sequence[Row]) -> tuple[float, ...]:
    """Higher is better: the worst person-recording's level + ENGAGED-or-not, then the
    average criterion. Robust to one recording pulling a threshold its way."""
    return (round(min(map(scoring.objective, scored)), 6), *on_average(scored))


#: The cap on the costlier error a choice keeps on its training people: the share of the
#: worst DISENGAGED person-recording's time called ENGAGED (a robot greeting someone who
#: is not engaging). Below the issue's 20 % for any person, so a new person has room;
#: 10 % leaves no rule but a 22° cone that misses a third of the engaged (measured).
FALSE_ENGAGED_CAP = 0.15


def capped(scored: Sequence[Row]) -> tuple[float, ...]:
    """Higher is better: within the cap on the worst person-recording's false ENGAGED
    first (beyond it, the less the better), then the average criterion."""
    worst = max((r.false_engaged for r in scored if r.false_engaged is not None), default=0.0)
    return (-max(0.0, round(worst - FALSE_ENGAGED_CAP, 6)), *on_average(scored))


#: How far below hri_engagement's rule any one person-recording may fall (its ENGAGED-or-
#: not, the rule's on the same row): a candidate farther below on anyone is out however
#: good its mean.
BELOW_RULE = 0.10

Key = tuple[str, str]  # (recording, person)
Rank = Callable[[Sequence[Row]], tuple[float, ...]]


def shortfall(scored: Sequence[Row], rule: Mapping[Key, float]) -> float:
    """How far the worst person-recording falls below the rule's ENGAGED-or-not on its
    row, beyond ``BELOW_RULE`` (0 when none does)."""
    worst = max(
        (rule[r.recording, r.person] - r.engaged_or_not for r in scored if not r.ceiling),
        default=0.0,
    )
    return max(0.0, round(worst - BELOW_RULE, 6))


def criteria(rule: Mapping[Key, float]) -> dict[str, Rank]:
    """How a family picks its candidate on the training person-recordings: the costlier
    error capped first, so that within a family it is the incumbent the others must beat
    beyond their interval; and *beside the rule*: no training person-recording
    far below the rule's figure on its row first, then the costlier error capped."""

    def beside_rule(scored: Sequence[Row]) -> tuple[float, ...]:
        return (-shortfall(scored, rule), *capped(scored))

    return {
        "false ENGAGED capped": capped,
        "on average": on_average,
        "at worst": at_worst,
        "beside the rule": beside_rule,
    }
