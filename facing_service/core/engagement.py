"""Engagement: from "facing now" to "engaging with the robot", quickly and without flicker.

Pure functions over plain values; the clock is the caller's (seconds). ``observe`` folds a
pose into a body's engagement by its params' ``Model``: the facing score's machine (this
module, below), soft evidence that accumulates (``core.evidence``), or hri_engagement's
rule (``core.rule``, ``--engagement rule``).

**Facing score** in [0, 1]: 1 when the body squarely faces the robot (inside the facing
cone) at a comfortable distance; it falls off linearly with the angle beyond the cone (to 0
at ``threshold + falloff_deg``) and with the horizontal distance beyond ``near_m`` (to 0 at
``far_m``, past the social zone). An undefined angle (robot straight above or below)
scores 0. With the defaults:

    angle (deg)  ≤20   25    30    35    40   ≥45      distance (m)  ≤2.5  3.0  3.5  4.0  ≥4.5
    angle factor  1.0  0.8   0.6   0.4   0.2  0.0      factor         1.0  0.75 0.5  0.25 0.0

and the score is the product of the two factors.

**Levels** (as hri_msgs/EngagementLevel): UNKNOWN 0, DISENGAGED 1, ENGAGING 2, ENGAGED 3,
DISENGAGING 4. The score is smoothed by an exponentially weighted average with time
constant ``tau_s`` (dt-aware, so dropped frames weigh correctly); the smoothed score
enters ENGAGING at ``engage_above`` and must hold there ``engage_dwell_s``, with the
latest sample above it too, to become ENGAGED; ENGAGED turns DISENGAGING below
``disengage_below`` and DISENGAGED after ``disengage_dwell_s`` unless it recovers. Two
thresholds plus dwell times keep tracker noise (several degrees of yaw jitter) from
flickering the level, while the short time constant keeps reactions under a second (see
benchmarks/engagement/simulated.py).

**Two speeds** (heads, chosen on real recordings: docs/engagement.md): ENGAGING is the
quick signal (the smoothed score crossing ``engage_above``: someone turning toward the
robot); with ``sustain_s`` set, ENGAGED (what a robot greets on) needs every sample of the
last ``sustain_s`` in the cone, so a glance, however often repeated, never engages.

**Steadiness** (heads, chosen on real recordings: docs/engagement.md): a person who
attends to the robot holds their head still toward it; one looking around sweeps through
the cone. The machine keeps the recent mean direction of the robot in the frame (an
exponentially weighted average with time constant ``steady_tau_s``); the score is scaled
by 1 while the direction stays within ``steady_deg`` of it, falling to 0 at twice that.
Off (``steady_deg`` None) unless asked for.

**A soft vote** (heads): hri_engagement's rule votes every tick whether the face
is within its wide field and near enough, and engages on the mean of the last 10 s. Here
the vote is whether the face is within ``vote_deg`` of the robot, kept as an exponentially
weighted share of recent samples (time constant ``vote_tau_s``, starting from 0, so it
needs about ``vote_tau_s * ln(1 / (1 - vote_share))`` of votes to reach ``vote_share``);
while the share is at ``vote_share`` or above the person is *attending*: ENGAGED too (the
latest sample voting), and held there, however their head roams within the field. It
tolerates a person's own offset where one cone cannot (an engaged head that sits at 29°,
or roams in and out of the cone). Off (``vote_deg`` None) unless asked for.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum

from ..contract.levels import Level
from . import evidence
from . import rule as hri_rule
from .mutual_gaze import GazeParams, Vector, votes_engaged


class Zone(str, Enum):
    INTIMATE = "intimate"
    PERSONAL = "personal"
    SOCIAL = "social"
    PUBLIC = "public"


class Model(str, Enum):
    """Which machine decides a level: the facing score's (``cone``, this module), soft
    evidence that accumulates (``evidence``, ``core.evidence``), or hri_engagement's rule
    (``rule``, ``core.rule``)."""

    CONE = "cone"
    EVIDENCE = "evidence"
    RULE = "rule"


@dataclass(frozen=True, kw_only=True)
class EngagementParams:
    """The engagement machine's parameters. Those a user tunes have no default here:
    they come from ``config.Settings`` (``config.profiles.engagement_params``), their one
    source; the rest are fixed by the design."""

    threshold_deg: float  # the facing cone (the service's threshold)
    tau_s: float  # time constant of the smoothed score
    engage_above: float
    disengage_below: float
    engage_dwell_s: float
    disengage_dwell_s: float
    intimate_m: float
    personal_m: float
    social_m: float
    falloff_deg: float = 25.0  # the score reaches 0 this far beyond the cone
    near_m: float = 2.5  # full score up to this distance (well inside the social zone)
    far_m: float = 4.5  # no score from this distance
    fresh_s: float = 0.2  # promotion to ENGAGED needs an observation at most this old
    steady_deg: float | None = None  # the score falls from this wander to 0 at twice it
    steady_tau_s: float = 0.5  # time constant of the recent mean direction
    # ENGAGED only once every sample of the last this long scored at least engage_above
    # (sustained attention); None (the default, and the shipped profiles'): once ENGAGING
    # has held engage_dwell_s.
    sustain_s: float | None = None
    vote_deg: float | None = None  # a sample votes "attending" within this angle (None: off)
    vote_tau_s: float = 3.0  # time constant of the share of recent votes
    vote_share: float = 0.75  # attending from this share (the rule's mean vote 0.5)
    model: Model = Model.CONE
    gaze: GazeParams = field(default_factory=GazeParams)  # the evidence of both others
    rule: hri_rule.RuleParams = field(default_factory=hri_rule.RuleParams)
    memory_s: float = 2.0  # the evidence machine's memory (seconds of full evidence)


def vote(angle_deg: float | None, distance_m: float | None, p: EngagementParams) -> float:
    """1.0 when the sample votes "attending": the face within ``vote_deg`` of the robot,
    nearer than ``far_m`` (as the rule votes "not engaged" beyond its distance)."""
    if p.vote_deg is None or angle_deg is None or distance_m is None:
        return 0.0
    return 1.0 if angle_deg < p.vote_deg and distance_m < p.far_m else 0.0


def facing_score(angle_deg: float | None, distance_m: float | None, p: EngagementParams) -> float:
    if angle_deg is None or distance_m is None:
        return 0.0
    by_angle = min(1.0, max(0.0, 1.0 - (angle_deg - p.threshold_deg) / p.falloff_deg))
    by_distance = min(1.0, max(0.0, (p.far_m - distance_m) / (p.far_m - p.near_m)))
    return by_angle * by_distance


def steadiness(wander_deg: float, steady_deg: float) -> float:
    """1 while the head wanders at most ``steady_deg`` from its recent direction, 0 at
    twice that."""
    return min(1.0, max(0.0, 2.0 - wander_deg / steady_deg))


def _unit(v: Vector) -> Vector | None:
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return None if n < 1e-9 else (v[0] / n, v[1] / n, v[2] / n)


def _wander(heading: Vector, direction: Vector, alpha: float) -> tuple[float, Vector]:
    """The angle (degrees) between ``direction`` and the recent mean ``heading``, and the
    mean moved toward ``direction`` by ``alpha``."""
    cos = heading[0] * direction[0] + heading[1] * direction[1] + heading[2] * direction[2]
    wander = math.degrees(math.acos(max(-1.0, min(1.0, cos))))
    moved = _unit(
        (
            heading[0] + alpha * (direction[0] - heading[0]),
            heading[1] + alpha * (direction[1] - heading[1]),
            heading[2] + alpha * (direction[2] - heading[2]),
        )
    )
    return wander, moved or direction


def zone(distance_m: float | None, p: EngagementParams) -> Zone:
    if distance_m is None:
        return Zone.INTIMATE  # the robot straight above or below: as close as it gets
    if distance_m < p.intimate_m:
        return Zone.INTIMATE
    if distance_m < p.personal_m:
        return Zone.PERSONAL
    if distance_m < p.social_m:
        return Zone.SOCIAL
    return Zone.PUBLIC


@dataclass(frozen=True)
class Engagement:
    """One body's engagement: level, smoothed score, and when the level last changed."""

    level: Level = Level.UNKNOWN
    score: float = 0.0  # smoothed
    raw: float = 0.0  # the latest sample's score
    since: float = 0.0
    last: float | None = None  # time of the last sample
    heading: Vector | None = None  # recent mean direction of the robot (with steadiness)
    facing_since: float | None = None  # every sample since then scored >= engage_above
    attention: float = 0.0  # the share of recent samples that voted (with the soft vote)
    voted: float = 0.0  # the latest sample's vote
    evidence: float = 0.0  # accumulated (the evidence machine)
    votes: hri_rule.Votes | None = None  # the window of votes (the rule)


def observe(
    state: Engagement,
    t: float,
    p: EngagementParams,
    angle_deg: float | None,
    distance_m: float | None,
    robot: Vector,
    person: Vector,
) -> Engagement:
    """Fold one pose at time ``t`` into a body's engagement, by the params' model:
    ``robot`` is the robot in the body's frame, ``person`` the body in the base frame."""
    if p.model is Model.RULE:
        engaged = votes_engaged(robot, person, p.gaze)
        votes = hri_rule.step(state.votes or hri_rule.Votes(), t, engaged, p.rule)
        share = (sum(votes.votes) / len(votes.votes) + 1.0) / 2.0 if votes.votes else 0.0
        since = state.since if votes.level is state.level else t
        return Engagement(votes.level, share, share, since, t, votes=votes)
    if p.model is Model.EVIDENCE:
        dt = 0.0 if state.last is None else max(0.0, t - state.last)
        v = evidence.vote(facing_score(angle_deg, distance_m, p))
        held = evidence.accumulate(state.evidence, v, dt, p.memory_s)
        level = evidence.level(state.level, held, p.memory_s)
        since = state.since if level is state.level else t
        share = held / p.memory_s
        return Engagement(level, share, share, since, t, evidence=held)
    return step(
        state,
        t,
        facing_score(angle_deg, distance_m, p),
        p,
        robot,
        vote(angle_deg, distance_m, p),
    )


def step(
    state: Engagement,
    t: float,
    raw_score: float,
    p: EngagementParams,
    direction: Vector | None = None,
    voted: float = 0.0,
) -> Engagement:
    """Fold one scored sample at time ``t`` into the state; ``direction`` (the robot in
    the frame) scales the score by the head's steadiness when that is on; ``voted``: the
    sample's ``vote`` (with the soft vote on)."""
    dt = 0.0 if state.last is None else max(0.0, t - state.last)
    heading = state.heading
    if direction is not None and p.steady_deg is not None and (unit := _unit(direction)):
        if heading is None:
            heading = unit  # the first direction: nothing to have wandered from
        else:
            wander, heading = _wander(heading, unit, 1.0 - math.exp(-dt / p.steady_tau_s))
            raw_score *= steadiness(wander, p.steady_deg)
    attention = state.attention
    if state.last is None:
        score, level, since = raw_score, Level.DISENGAGED, t
    else:
        alpha = 1.0 - math.exp(-dt / p.tau_s)
        score = state.score + alpha * (raw_score - state.score)
        level, since = state.level, state.since
        if p.vote_deg is not None:  # the share starts from 0: one vote is no attention
            attention += (1.0 - math.exp(-dt / p.vote_tau_s)) * (voted - attention)
    facing_since = None
    if raw_score >= p.engage_above:
        facing_since = t if state.facing_since is None else state.facing_since
    # the constructor, not dataclasses.replace: this runs for every sample
    return advance(
        Engagement(level, score, raw_score, since, t, heading, facing_since, attention, voted),
        t,
        p,
    )


def advance(state: Engagement, t: float, p: EngagementParams) -> Engagement:
    """Transitions due at ``t`` (dwell times can expire between samples)."""
    level, score, since = state.level, state.score, state.since
    # Becoming (or again) ENGAGED also needs the person to face the robot *now*: the
    # smoothed score lags, and a 0.6 s glance would otherwise turn ENGAGED just after it
    # ended (seen in the evaluation: 16 of 21 spurious changes).
    fresh = state.last is not None and t - state.last <= p.fresh_s  # silence is no evidence
    now_facing = score >= p.engage_above and state.raw >= p.engage_above and fresh
    # The soft vote (when on): attending holds the person in, and engages them with the
    # latest sample voting, however the smoothed score of the cone moves.
    attending = p.vote_deg is not None and state.attention >= p.vote_share
    voting_now = attending and state.voted > 0.0 and fresh
    falling = score < p.disengage_below and not attending
    nxt = level
    if level is Level.DISENGAGED and (score >= p.engage_above or attending):
        nxt = Level.ENGAGING
    elif level is Level.ENGAGING:
        if falling:
            nxt = Level.DISENGAGED
        elif (now_facing and _held(state, t, p)) or voting_now:
            nxt = Level.ENGAGED
    elif level is Level.ENGAGED and falling:
        nxt = Level.DISENGAGING
    elif level is Level.DISENGAGING:
        if now_facing or voting_now:
            nxt = Level.ENGAGED
        elif t - since >= p.disengage_dwell_s:
            nxt = Level.DISENGAGED
    if nxt is level:
        return state
    return Engagement(
        nxt,
        state.score,
        state.raw,
        t,
        state.last,
        state.heading,
        state.facing_since,
        state.attention,
        state.voted,
    )


def _held(state: Engagement, t: float, p: EngagementParams) -> bool:
    """ENGAGING has lasted long enough to be ENGAGED: the face has stayed in the cone for
    ``sustain_s`` (when set), else ENGAGING has held ``engage_dwell_s``."""
    if p.sustain_s is None:
        return t - state.since >= p.engage_dwell_s
    return state.facing_since is not None and t - state.facing_since >= p.sustain_s
