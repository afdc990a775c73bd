"""What the service says, as keyed payloads: pure functions from the tracker's changes and
state to zenoh keys and JSON, in the order they must go out. No zenoh, no threads: the
shell hands the results to the outbox or to a query, and these are tested on their own.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from enum import Enum
from typing import Any, NamedTuple

from ..contract import keys
from ..contract.levels import Level
from ..contract.schemas import (
    Centre,
    EngagementEvent,
    EngagementState,
    FrameFacing,
    FrameGazing,
    FrameGroups,
    GazePair,
    Greeting,
    GroupState,
    Place,
)
from ..contract.stamps import Time
from ..core.records import BodyState, Changes, EngagementUpdate
from ..core.social.groups import Group
from ..core.social.join import JoinPose
from ..core.social.scene import ROBOT, SceneUpdate
from ..ros2.output import RosMessage
from .outbox import Kind, Publication

#: Selector parameters the queryable understands; zenoh reserves names starting with "_".
QUERY_PARAMETERS = frozenset({"threshold_deg"})


#: The output key spaces a query can reach the service through.
class QuerySpace(str, Enum):
    """The output key spaces a query can reach the service through (one queryable each)."""

    FACING = "facing"  # NS/bodies/<id>/facing/<frame>
    FRAME = "frame"  # NS/facing/<frame>
    ENGAGEMENT = "engagement"  # NS/bodies/<id>/engagement/<frame>
    GROUPS = "groups"  # NS/groups/<frame>
    GAZING = "gazing"  # NS/gazing/<frame>


QUERY_SPACES = tuple(QuerySpace)
#: Worked out over time, not re-decided per query: a what-if cone is refused there.
OVER_TIME = (QuerySpace.ENGAGEMENT, QuerySpace.GROUPS, QuerySpace.GAZING)
#: Scenes: a frame this service knows answers them with its empty lists.
SCENE_SPACES = (QuerySpace.GROUPS, QuerySpace.GAZING)


class Speaker(NamedTuple):
    """Who says a publication: the service's namespace (its keys) and instance (in every
    payload). One value for the pair every builder here takes."""

    namespace: str
    instance: str


def result_publications(states: Iterable[BodyState], us: Speaker) -> list[Publication]:
    """Each body's result on its key."""
    namespace, instance = us
    result = Kind.RESULT
    return [
        Publication(
            keys.facing_key(namespace, body_id=s.body_id, frame_id=s.frame_id),
            s.to_json(instance),
            result,
        )
        for s in states
    ]


def publications(changes: Changes, us: Speaker, results: bool = True) -> list[Publication]:
    """Everything one tracker call changed, in publishing order: per-body results (unless
    nobody listens to them: ``results`` False); then each engagement update (its state,
    then its event when the level changed); then the lost bodies' DELETEs; then the
    frames' aggregates."""
    namespace, instance = us
    out = result_publications(changes.results, us) if results else []
    for update in changes.engagement:
        if update.level is not Level.UNKNOWN:
            out.append(
                Publication(
                    keys.engagement_key(
                        namespace, body_id=update.body_id, frame_id=update.frame_id
                    ),
                    engagement_state(update, instance).model_dump_json().encode(),
                    Kind.ENGAGEMENT,
                )
            )
        if update.previous is not None:
            out.append(
                Publication(
                    keys.event_key(namespace, update.frame_id),
                    engagement_event(update, instance).model_dump_json().encode(),
                    Kind.EVENT,
                )
            )
    for body in changes.lost:
        out.append(
            Publication(
                keys.facing_key(namespace, body_id=body.body_id, frame_id=body.frame_id),
                None,
                Kind.RESULT,
            )
        )
        out.append(
            Publication(
                keys.engagement_key(namespace, body_id=body.body_id, frame_id=body.frame_id),
                None,
                Kind.ENGAGEMENT,
            )
        )
    out.extend(
        Publication(
            keys.frame_key(namespace, frame.frame_id), frame_json(frame, instance), Kind.FRAME
        )
        for frame in changes.frames
    )
    return out


def scene_publications(update: SceneUpdate, us: Speaker) -> list[Publication]:
    """A frame's scene changed: each group formed or changed (PUT) and dissolved
    (DELETE), then the frame's whole list; who faces whom when a pair changed."""
    (namespace, instance), frame = us, update.frame_id
    out = [
        Publication(
            keys.group_key(namespace, frame, str(g.id)),
            group_state(g, update.stamp).model_dump_json().encode(),
            Kind.SCENE,
        )
        for g in update.changed
    ]
    out += [
        Publication(keys.group_key(namespace, frame, str(gid)), None, Kind.SCENE)
        for gid in update.dissolved
    ]
    if update.groups_changed:
        out.append(
            Publication(
                keys.groups_key(namespace, frame), groups_json(update, instance), Kind.SCENE
            )
        )
    if update.gazing_changed:
        out.append(
            Publication(
                keys.gazing_key(namespace, frame), gazing_json(update, instance), Kind.SCENE
            )
        )
    return out


def place(pose: JoinPose) -> Place:
    return Place(x=pose.x, y=pose.y, yaw=pose.yaw)


def group_state(group: Group, stamp: Time) -> GroupState:
    """A group as published, with the stamp of the grouping that made it (its frame's)."""
    return GroupState(
        id=str(group.id),
        members=sorted(group.members - {ROBOT}, key=keys.natural_order),
        robot=group.robot,
        centre=Centre(x=group.centre[0], y=group.centre[1]),
        join=None if group.join is None else place(group.join),  # (None with the robot in)
        stamp=stamp.model(),
    )


def groups_json(update: SceneUpdate, instance: str) -> bytes:
    return (
        FrameGroups(
            frame_id=update.frame_id,
            frame=update.frame_id,
            stamp=update.stamp.model(),
            groups=[group_state(g, update.stamp) for g in update.groups],
            people_left_out=update.left_out,
            greetings=[Greeting(body_id=g.body_id, place=place(g.pose)) for g in update.greetings],
            instance=instance,
        )
        .model_dump_json()
        .encode()
    )


def gazing_json(update: SceneUpdate, instance: str) -> bytes:
    pairs = [
        GazePair(sender=a, receiver=b, mutual=(b, a) in update.gazing)
        for a, b in sorted(update.gazing)
    ]
    return (
        FrameGazing(
            frame_id=update.frame_id,
            frame=update.frame_id,
            stamp=update.stamp.model(),
            pairs=pairs,
            people_left_out=update.left_out,
            instance=instance,
        )
        .model_dump_json()
        .encode()
    )


def ros_publications(messages: Iterable[RosMessage]) -> list[Publication]:
    """Messages for the robot's own topics (``--output ros2``), as the outbox carries them."""
    return [Publication(m.topic, m.payload, Kind.ROS, m.typename) for m in messages]


def query_replies(
    space: QuerySpace | str,
    us: Speaker,
    states: Iterable[BodyState],
    frames: Iterable[FrameFacing],
    engagements: Iterable[EngagementUpdate],
    scenes: Iterable[SceneUpdate] = (),
) -> list[tuple[str, bytes]]:
    """Every ``(key, payload)`` a query on ``space`` (one of ``QUERY_SPACES``) could be
    answered with; the shell keeps those whose key the query's selector matches."""
    space, (namespace, instance) = _space(space), us
    if space is QuerySpace.FACING:
        return [
            (
                keys.facing_key(namespace, body_id=s.body_id, frame_id=s.frame_id),
                s.to_json(instance),
            )
            for s in states
        ]
    if space is QuerySpace.FRAME:
        return [(keys.frame_key(namespace, f.frame_id), frame_json(f, instance)) for f in frames]
    if space is QuerySpace.ENGAGEMENT:
        return [
            (
                keys.engagement_key(namespace, body_id=e.body_id, frame_id=e.frame_id),
                engagement_state(e, instance).model_dump_json().encode(),
            )
            for e in engagements
        ]
    if space is QuerySpace.GROUPS:
        return [(keys.groups_key(namespace, u.frame_id), groups_json(u, instance)) for u in scenes]
    if space is QuerySpace.GAZING:
        return [(keys.gazing_key(namespace, u.frame_id), gazing_json(u, instance)) for u in scenes]
    raise AssertionError(f"a query space without replies: {space}")  # every member has them


def _space(space: QuerySpace | str) -> QuerySpace:
    try:
        return QuerySpace(space)
    except ValueError:
        known = ", ".join(s.value for s in QUERY_SPACES)
        raise ValueError(f"unknown query space {space!r}; known: {known}") from None


def threshold_parameter(
    parameters: Mapping[str, str], space: QuerySpace | str = QuerySpace.FACING
) -> float | None:
    """The query's ``threshold_deg``, None when absent; ValueError when it is bad, or
    asked of engagement, groups or who faces whom (worked out over time, not re-decided per
    query: a what-if there would be answered as if it were not asked)."""
    unknown = sorted(
        name for name in parameters if name not in QUERY_PARAMETERS and not name.startswith("_")
    )
    if unknown:
        raise ValueError(
            f"unknown parameter(s) {', '.join(unknown)}; known: "
            f"{', '.join(sorted(QUERY_PARAMETERS))}"
        )
    raw = parameters.get("threshold_deg")
    if raw is None:
        return None
    if (space := _space(space)) in OVER_TIME:
        raise ValueError(f"threshold_deg applies to facing results, not to {space.value}")
    try:
        value = float(raw)
    except ValueError:
        raise ValueError(f"threshold_deg must be a number, got {raw!r}") from None
    if not (math.isfinite(value) and 0.0 < value < 180.0):
        raise ValueError(f"threshold_deg must be in (0, 180), got {raw!r}")
    return value


def frame_json(frame: FrameFacing, instance: str) -> bytes:
    return frame.model_copy(update={"instance": instance}).model_dump_json().encode()


def _engagement_fields(update: EngagementUpdate, instance: str) -> dict[str, Any]:
    """What a level's state and its change event both say."""
    return {
        "instance": instance,
        "body_id": update.body_id,
        "frame_id": update.frame_id,
        "stamp": update.stamp.model(),
        "level": update.level,
        "level_value": int(update.level),
        "score": update.score,
        "zone": update.zone.value,
    }


def engagement_state(update: EngagementUpdate, instance: str) -> EngagementState:
    since = update.since.model()
    return EngagementState(**_engagement_fields(update, instance), since=since)


def engagement_event(update: EngagementUpdate, instance: str) -> EngagementEvent:
    assert update.previous is not None
    return EngagementEvent(**_engagement_fields(update, instance), previous=update.previous)
