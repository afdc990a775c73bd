"""The wire contract's outputs as pydantic models: per-body results, per-frame lists,
engagement states and events, the status reply, query errors; and the JSON Schemas of
``schemas/``, generated from these models and the input's (``poses``) by
``facing-service export-schemas schemas`` (a test fails when they drift).
"""

from __future__ import annotations

from typing import Any

import msgspec
from pydantic import BaseModel, Field, model_validator

from .levels import LevelName
from .poses import FastStamp, FastVector3, TransformStamped
from .stamps import NS_PER_S, Stamp


class Point(BaseModel):
    x: float
    y: float
    z: float


class FacingState(BaseModel):
    """Output per body: published for every accepted pose while anyone subscribes to
    results, and answered to queries."""

    body_id: str
    frame_id: str
    stamp: Stamp = Field(description="Stamp of the pose this result was computed from.")
    facing: bool
    angle_deg: float | None = Field(
        description="Horizontal angle between the body's x axis and the robot; null when "
        "the robot is straight above or below the body."
    )
    distance_m: float | None = Field(
        description="Horizontal distance from the body to the robot; null when degenerate."
    )
    robot_in_body: Point = Field(description="The robot origin in the body frame.")
    threshold_deg: float = Field(description="Half-angle of the facing cone applied.")
    position: Point = Field(
        description="The body's origin in the base frame (the pose's translation): where "
        "to draw it."
    )
    heading_deg: float = Field(
        description="Where the body's x axis points in the base frame's ground plane, as a "
        "yaw from the base frame's x axis, in (-180, 180]."
    )
    instance: str | None = Field(
        default=None,
        description="The service instance that produced it (its token is "
        "NS/services/facing/<instance>): consumers drop what a dead instance said.",
    )


class _FastFacingState(msgspec.Struct, gc=False):
    """``FacingState``'s fields in its order, for msgspec's encoder (the hot path)."""

    body_id: str
    frame_id: str
    stamp: FastStamp
    facing: bool
    angle_deg: float | None
    distance_m: float | None
    robot_in_body: FastVector3
    threshold_deg: float
    position: FastVector3
    heading_deg: float
    instance: str | None


_ENCODE = msgspec.json.Encoder().encode


def facing_state_json(
    body_id: str,
    frame_id: str,
    stamp: int,
    facing: bool,
    angle_deg: float | None,
    distance_m: float | None,
    robot_in_body: tuple[float, float, float],
    threshold_deg: float,
    position: tuple[float, float, float],
    heading_deg: float,
    instance: str | None = None,
) -> bytes:
    """The JSON of a ``FacingState``, by msgspec's encoder: the service's hot path, one
    per accepted pose. Building and dumping the pydantic model cost ~5 us; formatting by
    hand (f-strings, each float's repr) 2.4 us; this 0.7 us (each timed alone). A
    test checks it against ``FacingState``. A negative zero (``-Rᵀt`` of a body at
    z = 0) is said as 0.0: ``+ 0.0`` makes it one.
    """
    sec, nanosec = divmod(stamp, NS_PER_S)  # (a Time: integer nanoseconds)
    r, p = robot_in_body, position
    return _ENCODE(
        _FastFacingState(
            body_id,
            frame_id,
            FastStamp(sec, nanosec),
            facing,
            angle_deg,
            distance_m,
            FastVector3(r[0] + 0.0, r[1] + 0.0, r[2] + 0.0),
            threshold_deg,
            FastVector3(p[0] + 0.0, p[1] + 0.0, p[2] + 0.0),
            heading_deg + 0.0,
            instance,
        )
    )


class FrameFacing(BaseModel):
    """Output per base frame: published whenever either list changes."""

    frame_id: str
    stamp: Stamp | None = Field(
        description="Stamp of the newest pose accepted in this frame; null before any."
    )
    bodies_facing: list[str]
    bodies_tracked: list[str]
    instance: str | None = Field(
        default=None,
        description="The service instance that produced it (its token is "
        "NS/services/facing/<instance>): consumers drop what a dead instance said.",
    )


class EngagementState(BaseModel):
    """Output per body on ``NS/bodies/<id>/engagement/<frame>``: published on every change
    of level and at a modest rate otherwise (``--engagement-period-s``)."""

    body_id: str
    frame_id: str
    stamp: Stamp = Field(description="Stamp of the newest pose behind this state.")
    level: LevelName = Field(
        description="UNKNOWN, DISENGAGED, ENGAGING, ENGAGED or DISENGAGING (a ``Level`` in Python)."
    )
    level_value: int = Field(description="As hri_msgs/EngagementLevel: 0 to 4, same order.")
    score: float = Field(description="The smoothed facing score, in [0, 1].")
    zone: str = Field(description="Proxemic zone: intimate, personal, social or public.")
    since: Stamp = Field(description="Stamp at which the current level began.")
    instance: str | None = Field(
        default=None,
        description="The service instance that produced it (its token is "
        "NS/services/facing/<instance>): consumers drop what a dead instance said.",
    )


class EngagementEvent(BaseModel):
    """A change of level, on ``NS/events/engagement/<frame>``."""

    body_id: str
    frame_id: str
    stamp: Stamp
    previous: LevelName
    level: LevelName
    level_value: int
    score: float
    zone: str
    instance: str | None = Field(
        default=None,
        description="The service instance that produced it (its token is "
        "NS/services/facing/<instance>): consumers drop what a dead instance said.",
    )


INSTANCE_DESCRIPTION = (
    "The service instance that produced it (its token is NS/services/facing/<instance>): "
    "consumers drop what a dead instance said."
)


class Centre(BaseModel):
    x: float
    y: float


class Place(BaseModel):
    """Where the robot should stand, and which way it should face, in the base frame."""

    x: float = Field(description="Metres.")
    y: float = Field(description="Metres.")
    yaw: float = Field(description="Radians from the base frame's +x, counter-clockwise.")


class GroupState(BaseModel):
    """One F-formation, on ``NS/groups/<frame>/<id>`` (DELETE when it dissolves) and in
    its frame's list."""

    id: str = Field(description="Stable while the group keeps most of its members.")
    members: list[str] = Field(description="Body ids, sorted; the robot is not one (see robot).")
    robot: bool = Field(description="The robot (the base frame's origin) is in the group.")
    centre: Centre = Field(description="The o-space centre in the base frame, metres.")
    join: Place | None = Field(
        default=None,
        description="Where the robot should stand to join the group: on its ring, clear of "
        "everyone, the free place nearest the robot, facing into the group. null when the "
        "robot is in the group (robot true), or when the ring has no room for it.",
    )
    stamp: Stamp | None = Field(
        default=None,
        description="Stamp of the newest pose behind the grouping that made this group as it "
        "is (its frame's, as in the frame's list): an event that arrives late says so. Always "
        "set by the service.",
    )


class Greeting(BaseModel):
    """A person ENGAGING or ENGAGED and in no group, and where the robot should stand to
    greet them: in front of them at a social distance, facing them."""

    body_id: str
    place: Place


class OfAFrame(BaseModel):
    """What is said of a whole base frame names it ``frame_id``, as results do (groups
    and gazing once said ``frame`` alone); ``frame``, its first name, is said too for
    the consumers that read it, and is enough on input."""

    frame_id: str = Field(default="", description="The base frame, named as results name it.")
    frame: str = Field(description="The same: its first name, kept for consumers that read it.")

    @model_validator(mode="after")
    def _named_once(self) -> OfAFrame:
        if not self.frame_id:
            self.frame_id = self.frame
        elif self.frame_id != self.frame:
            raise ValueError(f"frame_id {self.frame_id!r} and frame {self.frame!r} differ")
        return self


class FrameGroups(OfAFrame):
    """Every group of a base frame, on ``NS/groups/<frame>``: published when a group
    forms, changes or dissolves (an empty list: none), and answered as a queryable."""

    stamp: Stamp = Field(description="Stamp of the newest pose behind this grouping.")
    groups: list[GroupState]
    people_left_out: int = Field(
        description="People beyond --group-max-people (the farthest from the robot), "
        "not considered."
    )
    greetings: list[Greeting] = Field(
        default_factory=list,
        description="Each person ENGAGING or ENGAGED and in no group, with where to greet "
        "them (none where someone else stands in that place).",
    )
    instance: str | None = Field(default=None, description=INSTANCE_DESCRIPTION)


class GazePair(BaseModel):
    sender: str = Field(description='Who faces: a body id, or "" for the robot (REP 155).')
    receiver: str = Field(description='Whom: a body id, or "" for the robot.')
    mutual: bool = Field(description="The receiver faces the sender too.")


class FrameGazing(OfAFrame):
    """Who faces whom in a base frame, on ``NS/gazing/<frame>``: published when a pair
    starts or stops facing, and answered as a queryable. A faces B when B is within A's
    facing cone (the rule for the robot, with B in its place, and its hysteresis)."""

    stamp: Stamp
    pairs: list[GazePair]
    people_left_out: int
    instance: str | None = Field(default=None, description=INSTANCE_DESCRIPTION)


class InputHealth(BaseModel):
    """Whether the service hears its input: a link that stalls is held, and
    said here, in the log and by ``health``."""

    last_heard_s: float | None = Field(
        description="Seconds since anything last came from the input (poses, a robot's "
        "topics); null before anything did."
    )
    silent: bool = Field(
        description="Nothing heard for longer than the input's own rate explains (at least "
        "--silent-after-s) with people tracked: they are held as they were (nobody goes "
        "stale) for up to --hold-silent-s after their own last pose."
    )
    held: int = Field(description="People held now (0 unless silent).")
    silences: int = Field(description="How many times the input went silent.")
    longest_silence_s: float = Field(description="The longest silence that has ended.")


#: ROS 2 findings that mean the input gives nobody's results at all (``health
#: --require-input`` fails on them): nothing read, or nothing that can be looked up.
INPUT_BROKEN = frozenset(
    {"no_ros_input", "ros_input_elsewhere", "base_frame_not_in_tree", "people_not_connected"}
)


class Ros2Status(BaseModel):
    """What a service on ROS 2 input (``--input ros2``) knows of its robot."""

    format: str = Field(description='"rmw_zenoh" or "bridge" (--ros-format).')
    distro: str = Field(
        description='The rmw_zenoh form answered in: "humble" (TypeHashNotSupported) or '
        '"jazzy" (RIHS01 type hashes: Jazzy, Kilted, Rolling).'
    )
    attachment: str = Field(
        description='rmw_zenoh attachment layout answered in: "current" (33 bytes) or '
        '"keyed" (before Humble 0.1.2 / Jazzy 0.2.4).'
    )
    forms: list[str] = Field(
        description='Every form answered in, "<distro>/<attachment>", the first as above: '
        "more than one when robots of different distros share the router (each is answered "
        "in its own)."
    )
    form_changes: int = Field(
        description="Times the forms answered in changed after the first was learned (a "
        "new form needs sustained evidence from samples that decode; one silent for 10 s "
        "is dropped)."
    )
    form_from: str = Field(
        description="Why that form: the key it was learned from, --ros-distro, or that "
        "nothing was learned yet (the default)."
    )
    publishers: dict[str, str] = Field(
        description="Per read topic: the nodes publishing it (rmw_zenoh liveliness tokens) "
        "and how many publishers (attachment GIDs) its samples came from; bounded."
    )
    tf_clears: int = Field(description="TF buffer clears: /tf time went back.")
    tf_clears_refused: int = Field(
        description="Clears not made: time went back again within 2 s of the last clear."
    )
    tracked_flaps: int = Field(
        description="Times a person left a tracked list and came back within 1 s."
    )
    findings: dict[str, str] = Field(
        description="Why people give no results, now: code -> one line to act on "
        "(no_ros_input, ros_input_elsewhere, base_frame_not_in_tree, "
        "tracked_frames_missing, people_not_connected, time_went_back, ros_forms_mixed, "
        "tf_clears_refused, tracked_flapping). Empty when none."
    )


class ServiceStatus(BaseModel):
    """Reply of ``NS/services/facing/<instance>/status``: health, counters, config."""

    status: str = Field(
        description='"ok"; "degraded" while the worker\'s last batch raised (counted in '
        'worker_errors, logged; back to "ok" when a batch succeeds); "no router" while the '
        "session has had no router or peer for over 5 s (a router restarting is shorter: "
        'see outage_s); "failed" when an internal thread died.'
    )
    instance: str
    version: str
    zenoh_id: str
    uptime_s: float
    config: dict[str, Any] = Field(
        description="The settings in force, with every value that may hold a secret "
        "(zenoh --cfg values outside an allow-list, endpoints' '#' config) redacted."
    )
    bodies_tracked: dict[str, int] = Field(description="Bodies tracked, per base frame.")
    bodies_tracked_total: int
    counters: dict[str, int] = Field(
        description="samples_accepted, results_published, results_superseded, "
        "deletes_published, frames_published, engagement_published, events_published, "
        "queries_answered, queries_refused, publish_errors, tf_lookups_unresolved, "
        "ros_published, scene_published, scene_people_left_out, clock_restarts, worker_errors: "
        "every one present from the start (scene_published: groups, group and who-faces-whom "
        "publications; scene_people_left_out: people beyond --group-max-people, summed "
        "over the scenes said; clock_restarts: bodies whose tracker's clock started over, "
        "lost and followed on the new clock). Read with the outbox depth: all accepted and an "
        "outbox_depth of 0 means all sent."
    )
    rejected: dict[str, int] = Field(description="Rejected samples per reason (all reasons).")
    connected: dict[str, list[str]] = Field(
        default_factory=dict,
        description="zenoh ids of the routers and peers this service's session is "
        "connected to now: empty while its endpoints are unreachable.",
    )
    outage_s: float | None = Field(
        None,
        description="Seconds since the session, told where to connect, last had a router "
        "or peer (lost, or never reached yet); null while it has one.",
    )
    inbox_depth: int = Field(
        description="Queries and a robot's side topics received, not yet handled (the input "
        "samples' own zenoh channel cannot report its depth)."
    )
    outbox_depth: int = Field(description="Publications decided, not yet sent.")
    results_heard: bool = Field(
        True,
        description="Whether a subscriber matches a result key, as zenoh last told the "
        "service: while false, results are neither formatted nor sent (results_published "
        "stands still; every other output and every query goes on), and when one appears "
        "every tracked body's current result is said (but those already sent since).",
    )
    input: InputHealth | None = Field(
        None, description="Whether the input is heard, or silent and its people held."
    )
    ros2: Ros2Status | None = Field(
        None, description="With --input ros2: the robot's form and what stops results."
    )


class QueryError(BaseModel):
    """Payload of an error reply to a query: ``bad_parameter`` (a bad selector parameter),
    ``unknown_frame`` (a frame this service does not know; the detail names those it
    tracks), ``empty_frame`` (per-body keys of a frame with nobody in it now),
    ``not_tracked`` (per-body keys of a body not in a frame where others are)."""

    error: str
    detail: str


#: File name in ``schemas/`` -> model. Input models validate; output models serialize.
SCHEMA_FILES: dict[str, tuple[type[BaseModel], str]] = {
    "pose.schema.json": (TransformStamped, "validation"),
    "facing_state.schema.json": (FacingState, "serialization"),
    "frame_facing.schema.json": (FrameFacing, "serialization"),
    "query_error.schema.json": (QueryError, "serialization"),
    "engagement_state.schema.json": (EngagementState, "serialization"),
    "engagement_event.schema.json": (EngagementEvent, "serialization"),
    "status.schema.json": (ServiceStatus, "serialization"),
    "frame_groups.schema.json": (FrameGroups, "serialization"),
    "group_state.schema.json": (GroupState, "serialization"),
    "frame_gazing.schema.json": (FrameGazing, "serialization"),
}


def json_schemas() -> dict[str, dict[str, Any]]:
    """The JSON Schemas of the wire contract, keyed by their file name in ``schemas/``."""
    return {
        name: model.model_json_schema(mode=mode)  # type: ignore[arg-type]
        for name, (model, mode) in SCHEMA_FILES.items()
    }
