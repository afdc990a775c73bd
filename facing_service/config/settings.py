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

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from ..contract import keys
from ..contract.poses import DEFAULT_MAX_PAYLOAD_BYTES
from ..contract.robot import DEFAULT_MAX_FRAMES, DEFAULT_MAX_MESSAGE_BYTES, Distro
from .disclosure import public_endpoint
from .endpoints import endpoint_problem

LogLevel = Literal["DEBUG", "INFO", "WARNING", "ERROR", "CRITICAL"]


def default_instance() -> str:
    """``<host name>-<pid>``, made a valid key chunk: unique per process on a network."""
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{socket.gethostname()}-{os.getpid()}")
    return name[-64:]


SERVICE, ENGAGEMENT, HEADS = "service", "engagement levels", "heads: face frames, from ROS 2 input"
GROUPS = "groups: who faces whom, F-formations"
ROS_IN = "ROS 2 input: a robot's own /tf and /humans/* topics"
ROS_OUT = "ROS 2 output: our results on the robot's own topics, beside the JSON keys"
ZENOH = "zenoh session"


def _flag(
    description: str,
    group: str = SERVICE,
    *,
    short: str | None = None,
    metavar: str | None = None,
    shown: str | None = None,
) -> dict[str, Any]:
    """A setting's flag: its help (the description), group, short form, metavar, and the
    default as the docs say it when the value itself would not (``shown``)."""
    extra = {"group": group, "short": short, "metavar": metavar, "shown": shown}
    return {"description": description, "json_schema_extra": extra}


class Settings(BaseModel):
    """Every setting of ``facing-service run``: the single source of the CLI's flags and
    help, the ``FACING_*`` variables and docs/configuration.md's table."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    namespace: str = Field("hri", **_flag("key prefix, one or more chunks"))
    base_frame: str = Field(
        keys.ALL_FRAMES,
        **_flag(
            "the base frame to serve, or `*` for every frame (with `--input ros2`, `*` means "
            "REP 105's `base_link`, libhri's reference frame)"
        ),
    )
    threshold_deg: float = Field(
        20.0, gt=0.0, lt=180.0, **_flag("half-angle of the facing cone, in (0, 180)")
    )
    hysteresis_deg: float = Field(
        5.0,
        ge=0.0,
        lt=180.0,
        **_flag(
            "extra angle a facing body may turn before it stops facing; `0` decides "
            "sample by sample"
        ),
    )
    stale_after_s: float = Field(
        2.0,
        gt=0.0,
        allow_inf_nan=False,
        **_flag("a body with no accepted pose for this long is lost"),
    )
    max_payload_bytes: int = Field(
        DEFAULT_MAX_PAYLOAD_BYTES, gt=0, **_flag("larger pose payloads are rejected")
    )
    max_bodies: int = Field(
        10_000,
        gt=0,
        **_flag("most bodies tracked over all frames; new ones beyond are rejected (`capacity`)"),
    )
    engage_above: float = Field(
        0.6, gt=0.0, le=1.0, **_flag("smoothed score at which a body starts ENGAGING", ENGAGEMENT)
    )
    disengage_below: float = Field(
        0.35,
        ge=0.0,
        lt=1.0,
        **_flag("smoothed score below which ENGAGED turns DISENGAGING", ENGAGEMENT),
    )
    engagement_tau_s: float = Field(
        0.25,
        gt=0.0,
        allow_inf_nan=False,
        **_flag("time constant of the smoothed score", ENGAGEMENT),
    )
    engage_dwell_s: float = Field(
        0.5,
        ge=0.0,
        allow_inf_nan=False,
        **_flag("ENGAGING must hold this long to become ENGAGED", ENGAGEMENT),
    )
    disengage_dwell_s: float = Field(
        0.6,
        ge=0.0,
        allow_inf_nan=False,
        **_flag("DISENGAGING must hold this long to become DISENGAGED", ENGAGEMENT),
    )
    engagement_period_s: float = Field(
        1.0,
        gt=0.0,
        allow_inf_nan=False,
        **_flag("an unchanged level is republished this often", ENGAGEMENT),
    )
    zones_m: list[float] = Field(
        [0.45, 1.2, 3.6],
        **_flag(
            "intimate, personal, social zone limits (public beyond)",
            ENGAGEMENT,
            metavar="INTIMATE,PERSONAL,SOCIAL",
        ),
    )
    # Heads (face frames, from ROS 2 input): chosen by cross-validation by person on the
    # shared recordings (benchmarks/crossval.py, docs/engagement.md).
    head_cone: Literal["3d", "planar"] = Field(
        "3d", **_flag("how a face's angle to the robot is measured: `3d` or `planar`", HEADS)
    )
    head_threshold_deg: float = Field(
        20.0,
        gt=0.0,
        lt=180.0,
        **_flag(
            "half-angle of a face's facing cone; a face starts ENGAGING at its edge",
            HEADS,
        ),
    )
    head_falloff_deg: float = Field(
        20.0,
        gt=0.0,
        lt=180.0,
        **_flag("a face's engagement score reaches 0 this far beyond its cone", HEADS),
    )
    head_engagement_tau_s: float = Field(
        2.0, gt=0.0, allow_inf_nan=False, **_flag("time constant of a face's smoothed score", HEADS)
    )
    head_dwell_s: float = Field(
        1.0,
        ge=0.0,
        allow_inf_nan=False,
        **_flag("a face's ENGAGING and DISENGAGING must hold this long", HEADS),
    )
    head_engaged_after_s: float = Field(
        0.0,
        ge=0.0,
        le=60.0,
        allow_inf_nan=False,
        **_flag(
            "a face becomes ENGAGED once it has stayed in its cone this long, every sample "
            "(0: once ENGAGING has held --head-dwell-s)",
            HEADS,
        ),
    )
    head_steady_deg: float = Field(
        0.0,
        ge=0.0,
        allow_inf_nan=False,
        **_flag(
            "a face's score falls from this wander away from its recent direction, to 0 at "
            "twice it (0: steadiness off)",
            HEADS,
        ),
    )
    head_steady_tau_s: float = Field(
        0.5,
        gt=0.0,
        allow_inf_nan=False,
        **_flag("time constant of a face's recent direction (steadiness)", HEADS),
    )
    head_vote_deg: float = Field(
        24.0,
        ge=0.0,
        lt=180.0,
        allow_inf_nan=False,
        **_flag(
            'a face votes "attending" within this angle of the robot; attending (the share '
            "of recent votes at --head-vote-share) makes it ENGAGED and holds it there "
            "(0: the vote off)",
            HEADS,
        ),
    )
    head_vote_tau_s: float = Field(
        1.5,
        gt=0.0,
        le=60.0,
        allow_inf_nan=False,
        **_flag("time constant of a face's share of recent votes", HEADS),
    )
    head_vote_share: float = Field(
        0.75,
        gt=0.0,
        le=1.0,
        allow_inf_nan=False,
        **_flag("the share of recent votes from which a face is attending", HEADS),
    )
    group_hold_s: float = Field(
        0.3,
        ge=0.0,
        allow_inf_nan=False,
        **_flag("a new grouping is said once it has held this long (no flicker)", GROUPS),
    )
    group_rate_hz: float = Field(
        10.0,
        gt=0.0,
        le=1000.0,
        allow_inf_nan=False,
        **_flag("groups and who faces whom are worked out at most this often per frame", GROUPS),
    )
    group_max_people: int = Field(
        20,
        ge=1,
        le=1000,
        **_flag("people of one frame considered for groups, nearest first (O(N^2))", GROUPS),
    )
    input: Literal["json", "ros2"] = Field(
        "json",
        **_flag(
            "`json` (our pose keys) or `ros2` (a robot's `/tf` and `/humans/*` topics)", ROS_IN
        ),
    )
    ros_format: Literal["rmw_zenoh", "bridge"] = Field(
        "rmw_zenoh", **_flag("`rmw_zenoh`, or `bridge` (zenoh-bridge-ros2dds)", ROS_IN)
    )
    ros_distro: Literal["auto", "humble", "jazzy"] = Field(
        "auto",
        **_flag(
            "rmw_zenoh's form to answer in: `auto` (learned from the robot's keys), `humble` "
            "(TypeHashNotSupported), `jazzy` (RIHS01 hashes: Jazzy, Kilted, Rolling)",
            ROS_IN,
        ),
    )
    ros_max_message_bytes: int = Field(
        DEFAULT_MAX_MESSAGE_BYTES,
        gt=0,
        **_flag(
            "a robot's message larger than this is refused undecoded (`payload_too_large`)",
            ROS_IN,
        ),
    )
    ros_max_frames: int = Field(
        DEFAULT_MAX_FRAMES,
        gt=0,
        **_flag(
            "most TF frames kept; frames silent for 10 s are forgotten to make room, and a "
            "transform naming one more is refused (`tf_too_many_frames`)",
            ROS_IN,
        ),
    )
    ros_domain_id: int = Field(
        0,
        ge=0,
        le=232,
        **_flag("`ROS_DOMAIN_ID`, 0-232 (rmw_zenoh keys start with it)", ROS_IN),
    )
    ros_namespace: str = Field(
        "", **_flag("ROS namespace (or the bridge's) prefixing every topic", ROS_IN)
    )
    output: Literal["json", "ros2"] = Field(
        "json",
        **_flag(
            "`ros2` also publishes on the robot's topics (engagement_status, facing lists)",
            ROS_OUT,
        ),
    )
    ros_node_name: str = Field(
        "facing_service",
        pattern=r"^[A-Za-z_][A-Za-z0-9_]*$",
        **_flag("our ROS node's name in the liveliness graph", ROS_OUT),
    )
    ros_engagement_rate_hz: float = Field(
        10.0, gt=0.0, le=1000.0, **_flag("engagement_status is republished this often", ROS_OUT)
    )
    ros_intents: bool = Field(
        False,
        **_flag("publish `ENGAGE_WITH` on `/intents` when a person becomes ENGAGED", ROS_OUT),
    )
    instance: str = Field(
        default_factory=default_instance,
        **_flag(
            "this service's name in `NS/services/facing/<instance>`", shown="<host name>-<pid>"
        ),
    )
    log_level: LogLevel = Field(
        "INFO", **_flag("`DEBUG`, `INFO`, `WARNING`, `ERROR` or `CRITICAL`")
    )
    # zenoh session; None means "as the config file says, else zenoh's default (peer)".
    mode: Literal["peer", "client", "router"] | None = Field(
        None,
        **_flag(
            "zenoh mode: `peer`, `client` or `router`",
            ZENOH,
            short="-m",
            shown="the config file's, else `peer`",
        ),
    )
    connect: list[str] = Field(
        [],
        **_flag(
            "endpoint to connect to, repeatable, e.g. `tcp/192.168.1.10:7447`",
            ZENOH,
            short="-e",
            metavar="ENDPOINT",
        ),
    )
    listen: list[str] = Field(
        [], **_flag("endpoint to listen on, repeatable", ZENOH, short="-l", metavar="ENDPOINT")
    )
    config: Path | None = Field(
        None,
        **_flag(
            "a zenoh JSON5 config file; the flags override it", ZENOH, short="-c", metavar="FILE"
        ),
    )
    no_multicast_scouting: bool = Field(False, **_flag("disable multicast discovery", ZENOH))
    reconnect_s: list[float] = Field(
        [0.25, 1.0],
        **_flag(
            "after a lost link, the first retry after FIRST seconds, doubling up to MOST "
            "(zenoh's own 1,4 left results stopped 4 s after a router came back); a "
            "`connect/retry` of the config file or --cfg wins",
            ZENOH,
            metavar="FIRST,MOST",
        ),
    )
    exit_without_router: bool = Field(
        False,
        **_flag(
            "`run` in client mode: exit at once when no router answers, rather than wait "
            "for it (a robot boots in any order)",
            ZENOH,
        ),
    )
    cfg: list[str] = Field(
        [],
        **_flag(
            "any zenoh config key with a JSON5 value, repeatable, e.g. `--cfg "
            "'scouting/delay:0'`; applied last",
            ZENOH,
            metavar="KEY:VALUE",
        ),
    )

    @field_validator("namespace")
    @classmethod
    def _namespace(cls, value: str) -> str:
        return keys.validate_namespace(value)

    @field_validator("instance")
    @classmethod
    def _instance(cls, value: str) -> str:
        return keys.validate_name(value, "instance")

    @field_validator("base_frame")
    @classmethod
    def _base_frame(cls, value: str) -> str:
        return keys.validate_frame_filter(value)

    @field_validator("connect", "listen")
    @classmethod
    def _endpoints(cls, value: list[str], info: Any) -> list[str]:
        for endpoint in value:
            if reason := endpoint_problem(endpoint, listen=info.field_name == "listen"):
                raise ValueError(f"{public_endpoint(endpoint)}: {reason}")
        return value

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

    @field_validator("reconnect_s")
    @classmethod
    def _reconnect(cls, value: list[float]) -> list[float]:
        if len(value) != 2 or not 0 < value[0] <= value[1] <= 60:
            raise ValueError("reconnect_s is FIRST,MOST seconds, 0 < FIRST <= MOST <= 60")
        return value

    @field_validator("zones_m")
    @classmethod
    def _zones(cls, value: list[float]) -> list[float]:
        if len(value) != 3 or not 0 < value[0] < value[1] < value[2]:
            raise ValueError("zones_m is INTIMATE,PERSONAL,SOCIAL limits, increasing, > 0")
        return value

    @model_validator(mode="after")
    def _hysteresis(self) -> Settings:
        if self.disengage_below >= self.engage_above:
            raise ValueError("disengage_below must be below engage_above")
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

    @field_validator("cfg")
    @classmethod
    def _cfg(cls, value: list[str]) -> list[str]:
        for position, entry in enumerate(value, 1):
            key, sep, _ = entry.partition(":")
            if not (sep and key):  # the entry itself is not quoted: it may be a secret
                raise ValueError(f"entry {position} is not KEY:VALUE")
        return value
