"""Our results on the robot's own topics (``--output ros2``), beside our JSON keys, so a
ROS4HRI robot can replace hri_engagement with this service, unchanged.

Topics (under ``--ros-namespace``; messages from the upstream ``.msg`` files in ``msg/``):

    /humans/persons/<id>/engagement_status   hri_msgs/msg/EngagementLevel
        as hri_engagement publishes it: at once on a change of level, and every
        1/--ros-engagement-rate-hz s (10 Hz, its rate) while the person is tracked;
        UNKNOWN once when the person is lost, then the publisher is undeclared.
    /intents                                 hri_actions_msgs/msg/Intent (--ros-intents)
        ENGAGE_WITH, data {"recipient": "<person id>"}, when a person becomes ENGAGED.
    /humans/{bodies,faces,persons}/facing    hri_msgs/msg/IdsList
        the ids facing the robot in the base frame, whenever that set changes.
    /humans/interactions/groups              hri_msgs/msg/Group
        each group when it forms or changes, and every period while it lasts (as
        engagement_status); ``members`` empty once when it dissolves. The robot, when in
        a group, is the member "" (REP 155's id for it in Gaze).
    /humans/interactions/gazing              hri_msgs/msg/Gaze
        each pair (sender faces receiver; "" is the robot) when it starts facing.
    /humans/interactions/groups/<id>/join    geometry_msgs/msg/PoseStamped
        where the robot should stand to join a group it is not in: on the
        group's ring, facing into it; every period while the group has room, the
        publisher undeclared when it no longer has (or the robot joined, or it dissolved).
        A PoseStamped in the base frame is what a navigation goal is (Nav2's
        NavigateToPose, RViz's goal tool): no TF lookup between seeing it and going.
    /humans/{persons,bodies,faces}/<id>/greet geometry_msgs/msg/PoseStamped
        where the robot should stand to greet a person ENGAGING or ENGAGED in no group:
        in front of them at a social distance, facing them; likewise every period.

This pure part (``RosOutput``) turns the tracker's changes into messages;
``shell.ros_bus.RobotPublishers`` (the publisher thread's) sends them in the robot's
format: in rmw_zenoh's, every sample carries the attachment its subscriptions require,
and the node and each publisher hold the liveliness tokens ``ros2 node list`` /
``ros2 topic list`` read.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

from ..contract.keys import natural_order
from ..contract.levels import Level
from ..contract.schemas import FrameFacing
from ..contract.stamps import ZERO, Time
from ..core.records import Changes, EngagementUpdate
from ..core.snapshot import TurnSnapshot
from ..core.social.join import JoinPose
from ..core.social.scene import SceneUpdate
from . import types as ros2_types
from .markers import (
    MARKER_ARRAY,
    MARKERS_TOPIC,
    MarkerDrawer,
    PersonMarker,
    drawn,
    place_pose,
)

ENGAGEMENT_LEVEL = "hri_msgs/msg/EngagementLevel"
INTENT = "hri_actions_msgs/msg/Intent"
GROUP = "hri_msgs/msg/Group"
GAZE = "hri_msgs/msg/Gaze"
GROUPS_TOPIC = "/humans/interactions/groups"
POSE_STAMPED = "geometry_msgs/msg/PoseStamped"
#: RViz markers at most 10 Hz, whatever --ros-engagement-rate-hz (RViz draws no faster
#: usefully, and a MarkerArray of many people is the largest message we send).
MARKER_PERIOD_S = 0.1
GAZING_TOPIC = "/humans/interactions/gazing"
#: Intent.msg: "0 is the lowest priority, 128 is the default priority, 255 is the highest".
DEFAULT_PRIORITY = 128
#: Our subject prefixes -> the ROS4HRI kind whose facing list they go to. Subjects from
#: JSON input have no prefix: they are bodies.
FACING_TOPICS = {
    "body_": "/humans/bodies/facing",
    "face_": "/humans/faces/facing",
    "person_": "/humans/persons/facing",
}
PERSON = "person_"
#: Every topic this output publishes (patterns: ``*`` is one level) and its type, for
#: whoever subscribes to all of it (``replay --record``).
PUBLISHED_TOPICS = (
    ("/humans/persons/*/engagement_status", ENGAGEMENT_LEVEL),
    ("/intents", INTENT),
    ("/humans/*/facing", ros2_types.IDS_LIST),
    (GROUPS_TOPIC, GROUP),
    (f"{GROUPS_TOPIC}/*/join", POSE_STAMPED),
    ("/humans/*/*/greet", POSE_STAMPED),
    (GAZING_TOPIC, GAZE),
    (MARKERS_TOPIC, MARKER_ARRAY),
)


@dataclass(frozen=True, slots=True)
class RosMessage:
    """One message for the robot: a topic, its type, CDR bytes (None: undeclare the
    topic's publisher, the person is gone)."""

    topic: str
    typename: str
    payload: bytes | None


def engagement_status(update: EngagementUpdate) -> RosMessage:
    person = update.body_id.removeprefix(PERSON)
    message = ros2_types.message_type(ENGAGEMENT_LEVEL)(
        header=ros2_types.header(update.frame_id, update.stamp), level=int(update.level)
    )
    return RosMessage(
        f"/humans/persons/{person}/engagement_status",
        ENGAGEMENT_LEVEL,
        ros2_types.serialize(message, ENGAGEMENT_LEVEL),
    )


def engage_intent(person: str) -> RosMessage:
    """ENGAGE_WITH, filled as hri_engagement fills it (``intent`` and ``data``); the fields
    it leaves empty take the upstream constants: the person is the source (REP 155: the
    agent expressing the intent, by person id), the modality ``MODALITY_OTHER`` (seen, not
    said or touched), and the message's documented default priority."""
    intent = ros2_types.message_type(INTENT)
    message = intent(
        intent=intent.ENGAGE_WITH,
        data=json.dumps({"recipient": person}),
        source=person,
        modality=intent.MODALITY_OTHER,
        priority=DEFAULT_PRIORITY,
        confidence=1.0,
    )
    return RosMessage("/intents", INTENT, ros2_types.serialize(message, INTENT))


def facing_ids(frame: FrameFacing) -> dict[str, list[str]]:
    """The ids facing the robot in one base frame, by ROS4HRI facing list (every list,
    empty ones included)."""
    ids: dict[str, list[str]] = {topic: [] for topic in FACING_TOPICS.values()}
    for subject in frame.bodies_facing:
        prefix = _kind(subject)
        ids[FACING_TOPICS.get(prefix, "/humans/bodies/facing")].append(subject[len(prefix) :])
    return ids


def _kind(subject: str) -> str:
    """A subject's kind prefix (``body_``, ``face_``, ``person_``), "" for none."""
    return next((p for p in FACING_TOPICS if subject.startswith(p)), "")


def facing_list(frame: FrameFacing, topic: str, ids: list[str]) -> RosMessage:
    stamp = Time.from_model(frame.stamp) if frame.stamp else ZERO
    message = ros2_types.message_type(ros2_types.IDS_LIST)(
        header=ros2_types.header(frame.frame_id, stamp), ids=ids
    )
    return RosMessage(
        topic, ros2_types.IDS_LIST, ros2_types.serialize(message, ros2_types.IDS_LIST)
    )


def ros_id(subject: str) -> str:
    """A subject as REP 155 names it on interaction topics: its id without our kind
    prefix (a person's id where the robot has persons); the robot stays ""."""
    return subject[len(_kind(subject)) :]


def group_message(frame_id: str, stamp: Time, group_id: int, members: Any) -> RosMessage:
    message = ros2_types.message_type(GROUP)(
        header=ros2_types.header(frame_id, stamp),
        group_id=str(group_id),
        members=sorted((ros_id(m) for m in members), key=natural_order),
    )
    return RosMessage(GROUPS_TOPIC, GROUP, ros2_types.serialize(message, GROUP))


def gaze_message(frame_id: str, stamp: Time, sender: str, receiver: str) -> RosMessage:
    message = ros2_types.message_type(GAZE)(
        header=ros2_types.header(frame_id, stamp), sender=ros_id(sender), receiver=ros_id(receiver)
    )
    return RosMessage(GAZING_TOPIC, GAZE, ros2_types.serialize(message, GAZE))


def place_message(topic: str, frame_id: str, stamp: Time, place: JoinPose) -> RosMessage:
    message = ros2_types.message_type(POSE_STAMPED)(
        header=ros2_types.header(frame_id, stamp), pose=place_pose(place)
    )
    return RosMessage(topic, POSE_STAMPED, ros2_types.serialize(message, POSE_STAMPED))


def places(scene: SceneUpdate) -> list[RosMessage]:
    """Where the robot should stand in one frame: to join each group it is not in, to
    greet each person engaging in no group."""
    frame, stamp = scene.frame_id, scene.stamp
    out = [
        place_message(f"{GROUPS_TOPIC}/{g.id}/join", frame, stamp, g.join)
        for g in scene.groups
        if g.join is not None  # (None with the robot in the group)
    ]
    for greeting in scene.greetings:
        kind = _kind(greeting.body_id) or "body_"
        topic = f"/humans/{kind[:-1]}s/{ros_id(greeting.body_id)}/greet"
        out.append(place_message(topic, frame, stamp, greeting.pose))
    return out


def scene_messages(
    update: SceneUpdate, said_gazing: frozenset[tuple[str, str]]
) -> list[RosMessage]:
    """A frame's scene changed: its groups formed or changed, those dissolved (no
    members), and the pairs that started facing since ``said_gazing``."""
    frame, stamp = update.frame_id, update.stamp
    out = [group_message(frame, stamp, g.id, g.members) for g in update.changed]
    out += [group_message(frame, stamp, gid, ()) for gid in update.dissolved]
    out += [gaze_message(frame, stamp, a, b) for a, b in sorted(update.gazing - said_gazing)]
    return out


class RosOutput:
    """Which messages the tracker's changes call for, and when the periodic
    engagement_status is due (the caller's clock, seconds)."""

    def __init__(self, rate_hz: float, intents: bool) -> None:
        self.period_s = 1.0 / rate_hz
        self.intents = intents
        self.next_tick = float("-inf")  # due at once, then every period
        self._said_facing: dict[tuple[str, str], list[str]] = {}  # (frame, topic) -> ids
        self._said_gazing: dict[str, frozenset[tuple[str, str]]] = {}  # frame -> pairs
        self._drawers: dict[str, MarkerDrawer] = {}  # frame -> what its markers drew
        self._places: set[str] = set()  # the place topics said last period
        self._next_markers = float("-inf")  # markers at most every MARKER_PERIOD_S

    def on_changes(self, changes: Changes) -> list[RosMessage]:
        out: list[RosMessage] = []
        for update in changes.engagement:
            if not update.body_id.startswith(PERSON) or update.previous is None:
                continue  # unchanged levels go out on the periodic tick
            out.append(engagement_status(update))
            if update.level is Level.UNKNOWN:  # lost: said once, then the topic goes
                out.append(RosMessage(out[-1].topic, ENGAGEMENT_LEVEL, None))
            elif update.level is Level.ENGAGED and self.intents:
                out.append(engage_intent(update.body_id.removeprefix(PERSON)))
        for frame in changes.frames:
            out.extend(self._facing_changes(frame))
        return out

    def _facing_changes(self, frame: FrameFacing) -> list[RosMessage]:
        """The facing lists whose ids changed: a frame's aggregate also changes when only
        its stamp or its tracked bodies do, which is nothing to say on a facing list.
        Each list is said once at first, empty included (nobody faces: said so)."""
        out = []
        for topic, ids in facing_ids(frame).items():
            if self._said_facing.get((frame.frame_id, topic)) != ids:
                self._said_facing[(frame.frame_id, topic)] = ids
                out.append(facing_list(frame, topic, ids))
        return out

    def on_scene(self, update: SceneUpdate) -> list[RosMessage]:
        said = self._said_gazing.get(update.frame_id, frozenset())
        if update.gazing:
            self._said_gazing[update.frame_id] = update.gazing
        else:
            self._said_gazing.pop(update.frame_id, None)  # bounded: frames come and go
        return scene_messages(update, said)

    def tick(self, now: float, snapshot: TurnSnapshot) -> list[RosMessage]:
        """Every period: each tracked person's current level, as hri_engagement does,
        each current group, and the markers (every tracked person, by frame). ``snapshot``
        is read only when the period is due (the worker calls ``tick`` once ``next_tick``
        has come)."""
        if now < self.next_tick:
            return []
        self.next_tick = now + self.period_s
        out = [engagement_status(e) for e in snapshot.engagements if e.body_id.startswith(PERSON)]
        by_frame = {scene.frame_id: scene for scene in snapshot.scenes}
        placed: list[RosMessage] = []
        for scene in by_frame.values():
            out += [
                group_message(scene.frame_id, scene.stamp, g.id, g.members) for g in scene.groups
            ]
            placed += places(scene)
        now_said = {m.topic for m in placed}
        out += placed + [RosMessage(t, POSE_STAMPED, None) for t in sorted(self._places - now_said)]
        self._places = now_said
        if now < self._next_markers:
            return out
        self._next_markers = now + MARKER_PERIOD_S
        return out + self._markers(drawn(snapshot), by_frame)

    def _markers(
        self, people: dict[str, list[PersonMarker]], scenes: dict[str, SceneUpdate]
    ) -> list[RosMessage]:
        """Each frame's markers (people, groups), and the last DELETEs of a frame that
        emptied (then forgotten: bounded)."""
        out = []
        for frame in sorted(people.keys() | self._drawers.keys()):
            drawer = self._drawers.setdefault(frame, MarkerDrawer())
            scene = scenes.get(frame)
            stamp = scene.stamp if scene is not None else ZERO
            groups = scene.groups if scene is not None else ()
            greetings = scene.greetings if scene is not None else ()
            payload = drawer.draw(frame, stamp, people.get(frame, []), groups, greetings)
            out.append(RosMessage(MARKERS_TOPIC, MARKER_ARRAY, payload))
            if frame not in people:
                del self._drawers[frame]
        return out
