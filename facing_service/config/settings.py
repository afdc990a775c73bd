"""Settings of the service: command-line flags, ``FACING_*`` environment variables, defaults.

Precedence: a flag beats its environment variable, which beats the default. The zenoh
session is configured exactly like zenoh's own example programs (``-m -e -l -c
--no-multicast-scouting --cfg``): the ``--config`` file first, then the flags over it,
then each ``--cfg KEY:VALUE``.
"""

from __future__ import annotations

import os
import re
import socket
from pathlib import Path
from typing import Any, Literal

from pydantic import ConfigDict, field_validator, model_validator

from ..contract import keys
from ..contract.poses import DEFAULT_MAX_PAYLOAD_BYTES
from ..contract.robot import DEFAULT_MAX_FRAMES, DEFAULT_MAX_MESSAGE_BYTES, Distro
from .fields import (
    ENGAGEMENT,
    GROUPS,
    HEADS,
    ROS_IN,
    ROS_OUT,
    ZENOH,
    SessionChecks,
    flag,
)

LogLevel = Literal["DEBUG", "INFO", "WARNING", "ERROR", "CRITICAL"]


def default_instance() -> str:
    """``<host name>-<pid>``, made a valid key chunk: unique per process on a network."""
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{socket.gethostname()}-{os.getpid()}")
    return name[-64:]


class Settings(SessionChecks):
    """Every setting of ``facing-service run``: the single source of the CLI's flags and
    help, the ``FACING_*`` variables and docs/configuration.md's table."""

    # No setting is nan or infinite: said as "a finite number", not as a bound it missed.
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    namespace: str = flag("hri", "key prefix, one or more chunks")
    base_frame: str = flag(
        keys.ALL_FRAMES,
        "the base frame to serve, or `*` for every frame (with `--input ros2`, `*` means "
        "REP 105's `base_link`, libhri's reference frame)",
    )
    threshold_deg: float = flag(
        20.0, "half-angle of the facing cone, in (0, 180)", gt=0.0, lt=180.0
    )
    hysteresis_deg: float = flag(
        5.0,
        "extra angle a facing body may turn before it stops facing; `0` decides sample by sample",
        ge=0.0,
        lt=180.0,
    )
    stale_after_s: float = flag(2.0, "a body with no accepted pose for this long is lost", gt=0.0)
    silent_after_s: float = flag(
        1.0,
        "the input sent nothing for this long (at most half of --stale-after-s) with people "
        "tracked: it is silent (a link stalled), and they are held",
        gt=0.0,
    )
    hold_silent_s: float = flag(10.0, "a silent input's people are held at most this long "
                                "after their own last pose, then lost (0: never held)", ge=0.0,
                                le=3600.0)  # fmt: skip
    max_payload_bytes: int = flag(
        DEFAULT_MAX_PAYLOAD_BYTES, "larger pose payloads are rejected", gt=0
    )
    max_bodies: int = flag(
        10_000,
        "most bodies tracked over all frames; new ones beyond are rejected (`capacity`)",
        gt=0,
    )
    engagement: Literal["service", "rule"] = flag(
        "service",
        "whose engagement levels: `service` (this service's machines, docs/engagement.md) or "
        "`rule` (hri_engagement 2.0.1's rule exactly, for bodies and faces: --rule-*)",
        ENGAGEMENT,
    )
    rule_field_of_view_deg: float = flag(
        60.0,
        "hri_engagement's field_of_view: of the person's gaze and the robot's, in the "
        "visual social engagement score",
        ENGAGEMENT,
        gt=0.0,
        lt=90.0,
    )
    rule_max_distance_m: float = flag(
        4.0,
        "hri_engagement's max_distance: no engagement beyond it",
        ENGAGEMENT,
        gt=0.0,
        le=100.0,
    )
    rule_threshold: float = flag(
        0.5,
        "hri_engagement's engagement_threshold: a score above it votes engaged",
        ENGAGEMENT,
        gt=0.0,
        lt=1.0,
    )
    rule_window_s: float = flag(
        10.0, "hri_engagement's observation_window: the votes the rule averages", ENGAGEMENT,
        gt=0.0, le=600.0,
    )  # fmt: skip
    rule_rate_hz: float = flag(
        10.0, "hri_engagement's rate: votes a second", ENGAGEMENT, gt=0.0, le=1000.0
    )
    engage_above: float = flag(
        0.6, "smoothed score at which a body starts ENGAGING", ENGAGEMENT, gt=0.0, le=1.0
    )
    disengage_below: float = flag(
        0.35, "smoothed score below which ENGAGED turns DISENGAGING", ENGAGEMENT, ge=0.0, lt=1.0
    )
    engagement_tau_s: float = flag(0.25, "time constant of the smoothed score", ENGAGEMENT, gt=0.0)
    engage_dwell_s: float = flag(
        0.5,
        "ENGAGING must hold this long to become ENGAGED",
        ENGAGEMENT,
        ge=0.0,
    )
    disengage_dwell_s: float = flag(
        0.6,
        "DISENGAGING must hold this long to become DISENGAGED",
        ENGAGEMENT,
        ge=0.0,
    )
    engagement_period_s: float = flag(
        1.0, "an unchanged level is republished this often", ENGAGEMENT, gt=0.0
    )
    zones_m: list[float] = flag(
        [0.45, 1.2, 3.6],
        "intimate, personal, social zone limits (public beyond)",
        ENGAGEMENT,
        metavar="INTIMATE,PERSONAL,SOCIAL",
    )
    # Heads (face frames, from ROS 2 input): chosen by cross-validation by person on the
    # shared recordings (benchmarks/engagement/crossval.py, docs/engagement.md).
    head_model: Literal["cone", "evidence"] = flag(
        "cone",
        "a face's engagement machine (with --engagement service): `evidence` (its facing "
        "score as a graded vote, accumulated over --head-memory-s) or `cone` (the score "
        "smoothed, with dwell times and the soft vote)",
        HEADS,
    )
    head_memory_s: float = flag(
        2.0,
        "seconds of full evidence a face's evidence machine holds; ENGAGED at 3/4 of it",
        HEADS,
        gt=0.0,
        le=600.0,
    )
    head_cone: Literal["3d", "planar"] = flag(
        "3d", "how a face's angle to the robot is measured: `3d` or `planar`", HEADS
    )
    head_threshold_deg: float = flag(
        20.0,
        "half-angle of a face's facing cone; a face starts ENGAGING at its edge",
        HEADS,
        gt=0.0,
        lt=180.0,
    )
    head_facing_window_s: float = flag(
        0.4,
        "a face faces by the median of its angles over this long (their stamps), not its "
        "last pose's alone: a face tracker's angle swings from frame to frame; a turn is "
        "said about half of it later. 0 (with --hysteresis-deg 0): the rule pose by pose",
        HEADS,
        ge=0.0,
        le=2.0,
    )
    head_falloff_deg: float = flag(
        20.0,
        "a face's engagement score reaches 0 this far beyond its cone",
        HEADS,
        gt=0.0,
        lt=180.0,
    )
    head_engagement_tau_s: float = flag(
        2.0, "time constant of a face's smoothed score", HEADS, gt=0.0
    )
    head_dwell_s: float = flag(
        1.0,
        "a face's ENGAGING and DISENGAGING must hold this long",
        HEADS,
        ge=0.0,
    )
    head_vote_deg: float = flag(
        24.0,
        'a face votes "attending" within this angle of the robot; attending (the share '
        "of recent votes at --head-vote-share) makes it ENGAGED and holds it there "
        "(0: the vote off)",
        HEADS,
        ge=0.0,
        lt=180.0,
    )
    head_vote_tau_s: float = flag(
        1.5,
        "time constant of a face's share of recent votes",
        HEADS,
        gt=0.0,
        le=60.0,
    )
    head_vote_share: float = flag(
        0.75,
        "the share of recent votes from which a face is attending",
        HEADS,
        gt=0.0,
        le=1.0,
    )
    group_hold_s: float = flag(
        0.3,
        "a new grouping is said once it has held this long (no flicker); a member gone "
        "leaves at once",
        GROUPS,
        ge=0.0,
    )
    group_heading_s: float = flag(
        0.5,
        "a person's heading in groups: the mean of their recent readings, fading with this"
        " time constant (0: the newest reading alone)",
        GROUPS,
        ge=0.0,
        le=60.0,
    )
    group_memory_s: float = flag(
        4.0,
        "a pair is said together once the last seconds show them together for half of this"
        " longer than apart, and apart likewise (0: the newest frame alone)",
        GROUPS,
        ge=0.0,
        le=60.0,
    )
    group_rate_hz: float = flag(
        10.0,
        "groups and who faces whom are worked out at most this often per frame",
        GROUPS,
        gt=0.0,
        le=1000.0,
    )
    group_max_people: int = flag(
        20,
        "people of one frame considered for groups, nearest first (O(N^2))",
        GROUPS,
        ge=1,
        le=1000,
    )
    input: Literal["json", "ros2"] = flag(
        "json", "`json` (our pose keys) or `ros2` (a robot's `/tf` and `/humans/*` topics)", ROS_IN
    )
    ros_format: Literal["rmw_zenoh", "bridge"] = flag(
        "rmw_zenoh", "`rmw_zenoh`, or `bridge` (zenoh-bridge-ros2dds)", ROS_IN
    )
    ros_distro: Literal["auto", "humble", "jazzy"] = flag(
        "auto",
        "rmw_zenoh's form to answer in: `auto` (learned from the robot's keys), `humble` "
        "(TypeHashNotSupported), `jazzy` (RIHS01 hashes: Jazzy, Kilted, Rolling)",
        ROS_IN,
    )
    ros_max_message_bytes: int = flag(
        DEFAULT_MAX_MESSAGE_BYTES,
        "a robot's message larger than this is refused undecoded (`payload_too_large`)",
        ROS_IN,
        gt=0,
    )
    ros_max_frames: int = flag(
        DEFAULT_MAX_FRAMES,
        "most TF frames kept; frames silent for 10 s are forgotten to make room, and a "
        "transform naming one more is refused (`tf_too_many_frames`)",
        ROS_IN,
        gt=0,
    )
    ros_join_wait_s: float = flag(
        0.25,
        "a new face or body that no person links waits this long (its own stamps) before "
        "it is a participant of its own, for a person manager to link it (no double at "
        "each arrival); 0: at once, on a robot with no person manager",
        ROS_IN,
        ge=0,
        le=5,
    )
    ros_domain_id: int = flag(
        0, "`ROS_DOMAIN_ID`, 0-232 (rmw_zenoh keys start with it)", ROS_IN, ge=0, le=232
    )
    ros_namespace: str = flag("", "ROS namespace (or the bridge's) prefixing every topic", ROS_IN)
    output: Literal["json", "ros2"] = flag(
        "json",
        "`ros2` also publishes on the robot's topics (engagement_status, facing lists)",
        ROS_OUT,
    )
    ros_node_name: str = flag(
        "facing_service",
        "our ROS node's name in the liveliness graph",
        ROS_OUT,
        pattern=r"^[A-Za-z_][A-Za-z0-9_]*$",
    )
    ros_engagement_rate_hz: float = flag(
        10.0, "engagement_status is republished this often", ROS_OUT, gt=0.0, le=1000.0
    )
    ros_intents: bool = flag(
        False, "publish `ENGAGE_WITH` on `/intents` when a person becomes ENGAGED", ROS_OUT
    )
    instance: str = flag(
        None,
        "this service's name in `NS/services/facing/<instance>`",
        shown="<host name>-<pid>",
        default_factory=default_instance,
    )
    log_level: LogLevel = flag("INFO", "`DEBUG`, `INFO`, `WARNING`, `ERROR` or `CRITICAL`")
    # zenoh session; None means "as the config file says, else zenoh's default (peer)".
    mode: Literal["peer", "client", "router"] | None = flag(
        None,
        "zenoh mode: `peer`, `client` or `router`",
        ZENOH,
        short="-m",
        shown="the config file's, else `peer`",
    )
    connect: list[str] = flag(
        [],
        "endpoint to connect to, repeatable, e.g. `tcp/192.168.1.10:7447`",
        ZENOH,
        short="-e",
        metavar="ENDPOINT",
    )
    listen: list[str] = flag(
        [], "endpoint to listen on, repeatable", ZENOH, short="-l", metavar="ENDPOINT"
    )
    config: Path | None = flag(
        None, "a zenoh JSON5 config file; the flags override it", ZENOH, short="-c", metavar="FILE"
    )
    no_multicast_scouting: bool = flag(False, "disable multicast discovery", ZENOH)
    reconnect_s: list[float] = flag(
        [0.25, 1.0],
        "after a lost link, the first retry after FIRST seconds, doubling up to MOST "
        "(zenoh's own 1,4 left results stopped 4 s after a router came back); a "
        "`connect/retry` of the config file or --cfg wins",
        ZENOH,
        metavar="FIRST,MOST",
    )
    exit_without_router: bool = flag(
        False,
        "`run` in client mode: exit at once when no router answers, rather than wait "
        "for it (a robot boots in any order)",
        ZENOH,
    )
    cfg: list[str] = flag(
        [],
        "any zenoh config key with a JSON5 value, repeatable, e.g. `--cfg "
        "'scouting/delay:0'`; applied last",
        ZENOH,
        metavar="KEY:VALUE",
    )

    @field_validator("instance")
    @classmethod
    def _instance(cls, value: str) -> str:
        return keys.validate_name(value, "instance")

    @field_validator("ros_namespace")
    @classmethod
    def _ros_namespace(cls, value: str) -> str:
        value = value.strip("/")
        if value and not all(re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", c) for c in value.split("/")):
            raise ValueError("a ROS namespace is names of [A-Za-z0-9_] joined by '/'")
        return value

    @field_validator("log_level", mode="before")
    @classmethod
    def _log_level(cls, value: Any) -> Any:
        return value.upper() if isinstance(value, str) else value

    @field_validator("zones_m")
    @classmethod
    def _zones(cls, value: list[float]) -> list[float]:
        if len(value) != 3 or not 0 < value[0] < value[1] < value[2]:
            raise ValueError("zones_m is INTIMATE,PERSONAL,SOCIAL limits, increasing, > 0")
        return value

    @model_validator(mode="after")
    def _hysteresis(self) -> Settings:
        if self.disengage_below >= self.engage_above:
            raise ValueError(
                f"--disengage-below (FACING_DISENGAGE_BELOW, {self.disengage_below:g}) must be "
                f"below --engage-above (FACING_ENGAGE_ABOVE, {self.engage_above:g})"
            )
        return self

    @property
    def forced_distro(self) -> Distro | None:
        """``--ros-distro``, None when it is to be learned from the robot (``auto``)."""
        return None if self.ros_distro == "auto" else Distro(self.ros_distro)

    @property
    def ros_base_frame(self) -> str:
        """The frame ROS 2 input looks people up in: ``--base-frame``, or REP 105's
        ``base_link`` (libhri's default reference frame) when it is ``*``."""
        return "base_link" if self.base_frame == keys.ALL_FRAMES else self.base_frame
