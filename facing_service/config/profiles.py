"""What the settings make of the core's parameters: the engagement machine's, how chests
and heads are decided, the scenes', and the tracker a service runs. Kept apart from
``Settings`` (which only declares and checks the values) because this is where the
settings' *meaning* for the core lives."""

from __future__ import annotations

from dataclasses import replace

from ..contract import keys
from ..contract.robot import Distro, RosFormat
from ..core.engagement import EngagementParams, Model
from ..core.mutual_gaze import GazeParams
from ..core.records import Profile
from ..core.rule import RuleParams
from ..core.social.groups import GroupParams, ScaleParams
from ..core.social.memory import MemoryParams
from ..core.social.scene import SceneParams
from ..core.tracker import Tracker
from ..ros2.wire import Wire
from .settings import Settings


def engagement_params(settings: Settings) -> EngagementParams:
    """A body's engagement machine: the facing score's, or hri_engagement's rule for
    everyone with ``--engagement rule``."""
    s = settings
    intimate, personal, social = s.zones_m
    return EngagementParams(
        threshold_deg=s.threshold_deg,
        tau_s=s.engagement_tau_s,
        engage_above=s.engage_above,
        disengage_below=s.disengage_below,
        engage_dwell_s=s.engage_dwell_s,
        disengage_dwell_s=s.disengage_dwell_s,
        intimate_m=intimate,
        personal_m=personal,
        social_m=social,
        model=Model.RULE if s.engagement == "rule" else Model.CONE,
        gaze=GazeParams(s.rule_field_of_view_deg, s.rule_max_distance_m, s.rule_threshold),
        rule=RuleParams(s.rule_rate_hz, s.rule_window_s),
    )


def head_profile(settings: Settings) -> Profile:
    """How face frames are decided (ROS 2 input): see docs/ros2.md's evaluation.

    One story for heads: a face is facing inside its cone (``head_threshold_deg``), and
    its engagement score crosses ``engage_above`` exactly at the cone's edge (the score's
    full plateau is ``(1 - engage_above) * head_falloff_deg`` inside it), so a face that
    can engage is a face that faces, and one facing within the hysteresis band is one
    that has not dropped below ``disengage_below``: a person ENGAGED is never "not
    facing" for long, nor facing without a score that engages."""
    s = settings
    plateau = s.head_threshold_deg - (1.0 - s.engage_above) * s.head_falloff_deg
    body = engagement_params(s)  # the rule, with --engagement rule, is everyone's
    evidence = body.model is Model.CONE and s.head_model == "evidence"
    engagement = replace(
        body,
        threshold_deg=max(0.0, plateau),
        falloff_deg=s.head_falloff_deg,
        tau_s=s.head_engagement_tau_s,
        engage_dwell_s=s.head_dwell_s,
        disengage_dwell_s=s.head_dwell_s,
        vote_deg=s.head_vote_deg or None,
        vote_tau_s=s.head_vote_tau_s,
        vote_share=s.head_vote_share,
        model=Model.EVIDENCE if evidence else body.model,
        memory_s=s.head_memory_s,
    )
    return Profile(
        s.head_threshold_deg,
        s.hysteresis_deg,
        s.head_cone == "3d",
        engagement,
        s.head_facing_window_s,
    )


def scene_params(settings: Settings) -> SceneParams:
    """Who faces whom is the facing rule (body cone and hysteresis) between people; the
    groups' method keeps its one default set, lengths in metres and each o-space a ring
    of its people's own size (chosen by leave-one-dataset-out, docs/groups.md), and the
    groups are what the last seconds say (the memory's two lengths, chosen likewise)."""
    s = settings
    return SceneParams(
        GroupParams(),
        ScaleParams(),
        threshold_deg=s.threshold_deg,
        hysteresis_deg=s.hysteresis_deg,
        hold_s=s.group_hold_s,
        period_s=1.0 / s.group_rate_hz,
        max_people=s.group_max_people,
        memory=MemoryParams(s.group_heading_s, s.group_memory_s),
    )


def tracker_for(settings: Settings, head: Profile | None = None) -> Tracker:
    """The tracker a service with these settings runs (also the offline evaluation's, in
    benchmarks.engagement.crossval: the same decisions without the network, and no zenoh; ``head``:
    a head profile of its own, for the research knobs the evaluation searches)."""
    fixed = [] if settings.base_frame == keys.ALL_FRAMES else [settings.base_frame]
    return Tracker(
        settings.threshold_deg,
        settings.hysteresis_deg,
        settings.stale_after_s,
        frames=fixed,
        max_bodies=settings.max_bodies,
        engagement=engagement_params(settings),
        engagement_period_s=settings.engagement_period_s,
        head=head or head_profile(settings),
    )


def robot_wire(settings: Settings) -> Wire:
    """Where the robot's topics are on zenoh, and the form we write in before (or instead
    of) learning the robot's."""
    return Wire(
        RosFormat(settings.ros_format),
        settings.ros_domain_id,
        settings.ros_namespace,
        settings.forced_distro or Distro.JAZZY,
    )
