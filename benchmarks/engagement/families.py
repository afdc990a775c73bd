"""The ideas the engagement cross-validation compares (``crossval``): each the head
settings it searches from the simplest, the rest at the shipped defaults; and how one
candidate becomes the service's settings and its research knobs."""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from facing_service.config.profiles import head_profile, tracker_for
from facing_service.config.settings import Settings
from facing_service.core.tracker import Tracker

from .scoring import BASE_FRAME

#: The settings every candidate shares: the service as the recordings evaluation runs it.
BASE: dict[str, Any] = {"input": "ros2", "base_frame": BASE_FRAME}
CONES = (20.0, 22.0, 24.0, 26.0, 28.0, 30.0, 32.0)

#: Each idea, as the settings it searches (everything else: the shipped defaults), from
#: the simplest. The head's cone is in every one: it is the first thing any rule sets.
FAMILIES: dict[str, dict[str, tuple[Any, ...]]] = {
    # One parameter: the cone; falloff, smoothing and dwell at their defaults.
    "cone only": {"head_threshold_deg": CONES},
    # A narrower or wider band between starting to engage and dropping out (hysteresis).
    "cone, hysteresis": {"head_threshold_deg": CONES, "head_falloff_deg": (5.0, 10.0, 20.0, 30.0)},
    # UE-HRI's finding that a 1-2 s decision delay helps: longer dwell times allowed.
    "cone, decision delay": {
        "head_threshold_deg": CONES,
        "head_dwell_s": (0.5, 1.0, 1.5, 2.0, 3.0),
    },
    # Attention holds the head still toward the robot; looking around sweeps through the cone.
    "cone, steadiness": {
        "head_threshold_deg": CONES,
        "head_steady_deg": (3.0, 5.0, 8.0, 12.0),
    },
    "cone, steadiness and its time constant": {
        "head_threshold_deg": CONES,
        "head_steady_deg": (3.0, 5.0, 8.0, 12.0),
        "head_steady_tau_s": (0.25, 0.5, 1.0),
    },
    "cone, steadiness, decision delay": {
        "head_threshold_deg": CONES,
        "head_steady_deg": (3.0, 5.0, 8.0, 12.0),
        "head_dwell_s": (0.5, 1.0, 1.5, 2.0),
    },
    # Two speeds: ENGAGING as soon as the smoothed score crosses, ENGAGED once the face
    # has stayed in the cone, every sample, this long (sustained attention).
    # First with the time fixed by the delay the issue allows ENGAGED (half the rule's
    # 5.2 s: a person facing from the start is ENGAGED at 2.1 s), the cone alone chosen;
    # then the time chosen too.
    "cone, sustained attention 2 s": {
        "head_threshold_deg": CONES,
        "head_engaged_after_s": (2.0,),
    },
    "cone, sustained attention": {
        "head_threshold_deg": CONES,
        "head_engaged_after_s": (1.0, 1.5, 2.0, 2.5, 3.0),
    },
    # ... with a faster smoothed score: ENGAGING sooner, and ENGAGED left sooner.
    "cone, sustained attention, smoothing": {
        "head_threshold_deg": CONES,
        "head_engaged_after_s": (1.5, 2.0, 2.5),
        "head_engagement_tau_s": (0.5, 1.0, 2.0),
    },
    "cone, sustained attention, hysteresis": {
        "head_threshold_deg": CONES,
        "head_engaged_after_s": (1.5, 2.0, 2.5),
        "head_falloff_deg": (10.0, 20.0, 30.0),
    },
    "cone, sustained attention, steadiness": {
        "head_threshold_deg": CONES,
        "head_engaged_after_s": (1.5, 2.0, 2.5),
        "head_steady_deg": (0.0, 5.0, 8.0, 12.0),
    },
    # The rule's own evidence, shortened: a soft vote, the face within a field
    # of its own, whose share of recent samples engages a person and holds them however
    # their head roams. The cone is kept (24°, as chosen before) for the quick ENGAGING,
    # and with it the 2 s of sustained attention; the vote's field is searched from inside
    # the cone to the rule's own width (about 36° at these distances is where its score
    # votes), its memory from the quick (1.5 s: 2.1 s of votes to attend from nothing) to
    # the rule's own pace (4 s).
    "cone kept, sustained attention 2 s, soft vote": {
        "head_threshold_deg": (24.0,),
        "head_engaged_after_s": (2.0,),
        "head_vote_deg": (20.0, 22.0, 24.0, 26.0, 28.0, 30.0, 34.0),
        "head_vote_tau_s": (1.5, 2.5, 4.0),
    },
    # ... the vote alone engaging (no sustained attention), the cone searched too.
    "cone, soft vote": {
        "head_threshold_deg": CONES,
        "head_vote_deg": (20.0, 22.0, 24.0, 26.0, 28.0, 30.0, 34.0),
        "head_vote_tau_s": (1.5, 2.5, 4.0),
    },
    # Soft evidence that accumulates: the facing score as a graded vote (+1 in
    # the cone, -1 past its fall-off), summed over time within a memory, levels by the
    # rule's own thresholds on its share; no gate decides alone. The memory is its one
    # length; the cone (and where the votes turn negative) is the head's.
    "evidence: cone, memory": {
        "head_model": ("evidence",),
        "head_threshold_deg": CONES,
        "head_memory_s": (1.0, 1.5, 2.0, 3.0, 4.0),
    },
    "evidence: cone, fall-off, memory": {
        "head_model": ("evidence",),
        "head_threshold_deg": CONES,
        "head_falloff_deg": (5.0, 10.0, 20.0),
        "head_memory_s": (1.0, 2.0, 3.0),
    },
    # Everything free: shows what fitting many parameters to five people does.
    "every head parameter": {
        "head_threshold_deg": (24.0, 28.0, 32.0),
        "head_falloff_deg": (10.0, 20.0),
        "head_engagement_tau_s": (1.0, 2.0),
        "head_dwell_s": (0.5, 1.0, 1.5),
        "head_steady_deg": (0.0, 5.0),
    },
}


#: What a family that does not search it runs with: the rule before it was an idea (the
#: defaults hold the preferred idea's choice, which would leak into every other family).
BEFORE = {"head_engaged_after_s": (0.0,), "head_vote_deg": (0.0,), "head_model": ("cone",)}


#: Research knobs: searched here, never the product's flags (no user should
#: meet a knob that defaults to off and was never chosen): the head's engagement
#: parameter each sets, and the value that turns it off.
RESEARCH: dict[str, tuple[str, Any]] = {
    "head_steady_deg": ("steady_deg", None),  # steadiness
    "head_steady_tau_s": ("steady_tau_s", 0.5),
    "head_engaged_after_s": ("sustain_s", None),  # sustained attention
}


def setup(candidate: Mapping[str, Any]) -> tuple[Settings, dict[str, Any]]:
    """A candidate as the service's settings and the research knobs it sets beside them."""
    product = {k: v for k, v in candidate.items() if k not in RESEARCH}
    research = {RESEARCH[k][0]: v or RESEARCH[k][1] for k, v in candidate.items() if k in RESEARCH}
    return Settings(**BASE, **product), research


def research_tracker(settings: Settings, research: Mapping[str, Any]) -> Tracker:
    """The service's tracker, its head's engagement changed by the research knobs."""
    if not research:
        return tracker_for(settings)
    head = head_profile(settings)
    return tracker_for(settings, replace(head, engagement=replace(head.engagement, **research)))


def grid_of(family: str) -> dict[str, tuple[Any, ...]]:
    """A family's full grid: what it searches, and ``BEFORE`` where it does not."""
    return {**BEFORE, **FAMILIES[family]}


def candidates(grid: Mapping[str, Sequence[Any]]) -> list[dict[str, Any]]:
    names = sorted(grid)
    values = itertools.product(*(grid[name] for name in names))
    return [dict(zip(names, combination, strict=True)) for combination in values]
