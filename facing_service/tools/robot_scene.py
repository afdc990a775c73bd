"""A simulated ROS4HRI robot: the people of a ``Crowd`` as a robot running ROS4HRI's body
and face trackers and its person manager publishes them, message by message. Pure: the
messages come out as CDR bytes, and the shell puts them on zenoh or into a bag.

What it publishes, and why it is shaped so:

- ``/tf_static`` (transient-local), once: ``base_link`` (or the base frame given) ->
  ``head_camera_link`` (1.3 m
  up) -> ``head_camera_optical_frame`` (z forward, as cameras' optical frames are).
  Trackers publish in the optical frame, so the service composes a chain as tf2 does.
- ``/tf`` at the crowd's rate: ``body_<id>`` for every person (1 m up, x forward) and
  ``face_<id>`` for each face the camera sees (1.6 m up): a face is seen once it turns
  within ``FACE_SEEN_DEG`` of the camera at most ``FACE_RANGE_M`` away, and lost past
  ``FACE_LOST_DEG`` (detectors lose a face turning away, and a margin keeps one at the
  edge from blinking). ``/humans/bodies/tracked`` and ``/humans/faces/tracked`` with it.
- Persons (transient-local, published when they change): a face is first an anonymous
  person (``anonymous_person_<face id>``) linking that face and its body; once seen ``RECOGNISED_S``
  in all, it is recognised as a known person (the next of ``KNOWN_NAMES``), who links its
  face and its body (one human, one participant) while the anonymous one leaves the
  list. A known person links its body while the body is tracked and its face while it is
  seen, and is tracked while either is. People past the names stay anonymous.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from ..client.sim import Crowd, TrackedPose
from ..contract.stamps import Time
from ..core.tf.geometry import Quat, Vec, qinv, qmul, rotate
from ..ros2 import types as ros2_types

BASE_FRAME = "base_link"
CAMERA_LINK = "head_camera_link"
CAMERA_FRAME = "head_camera_optical_frame"
CAMERA_AT: Vec = (0.1, 0.0, 1.3)
#: x right, y down, z forward: the optical convention (roll -90°, yaw -90°).
OPTICAL: Quat = (-0.5, 0.5, -0.5, 0.5)
BODY_HEIGHT_M = 1.0
FACE_HEIGHT_M = 1.6
FACE_SEEN_DEG = 55.0
FACE_LOST_DEG = 65.0
FACE_RANGE_M = 3.5
RECOGNISED_S = 3.0
KNOWN_NAMES = ("ada", "grace", "alan")


@dataclass(frozen=True, slots=True)
class RobotMessage:
    """One message on one of the robot's topics; ``latched``: a transient-local topic."""

    topic: str
    typename: str
    cdr: bytes
    latched: bool = False


@dataclass
class _Human:
    """What the robot knows of one person of the crowd."""

    number: str  # the crowd's id without its letter: ids body b<n>, face f<n>
    face_seen: bool = False
    seen_s: float = 0.0
    name: str | None = None  # once recognised

    @property
    def body(self) -> str:
        return f"b{self.number}"

    @property
    def face(self) -> str:
        return f"f{self.number}"

    def person(self) -> str | None:
        """The person id tracked for this human now, if any."""
        if self.name is not None:
            return self.name
        return f"anonymous_person_{self.face}" if self.face_seen else None

    def links(self) -> dict[str, str]:
        """The person's ``face_id`` and ``body_id`` as published now."""
        if self.name is None:
            return {"face_id": self.face, "body_id": self.body}
        return {"face_id": self.face if self.face_seen else "", "body_id": self.body}


@dataclass
class RobotScene:
    """The robot's topics over time: ``start()`` once, ``step(dt)`` every tick, ``stop()``
    at the end (empty lists: a tracker that stops says its people are gone)."""

    crowd: Crowd
    base_frame: str = BASE_FRAME
    _humans: dict[str, _Human] = field(init=False, default_factory=dict)
    _names_given: int = field(init=False, default=0)
    _persons: tuple[str, ...] = field(init=False, default=())
    _links: dict[tuple[str, str], str] = field(init=False, default_factory=dict)

    def start(self) -> list[RobotMessage]:
        stamp = self._stamp()
        camera = _transform(stamp, self.base_frame, CAMERA_LINK, CAMERA_AT, (0.0, 0.0, 0.0, 1.0))
        optical = _transform(stamp, CAMERA_LINK, CAMERA_FRAME, (0.0, 0.0, 0.0), OPTICAL)
        return [_message("/tf_static", ros2_types.TF_MESSAGE, _tf([camera, optical]), True)]

    def step(self, dt: float) -> list[RobotMessage]:
        tick = self.crowd.step(dt)
        for lost in tick.lost:
            self._humans.pop(lost, None)
        stamp = self._stamp()
        transforms, bodies, faces = [], [], []
        for pose in tick.poses:
            human = self._humans.setdefault(pose.body_id, _Human(pose.body_id[1:]))
            transforms.append(_in_camera(stamp, f"body_{human.body}", pose, BODY_HEIGHT_M))
            bodies.append(human.body)
            if self._sees_face(human, pose, dt):
                transforms.append(_in_camera(stamp, f"face_{human.face}", pose, FACE_HEIGHT_M))
                faces.append(human.face)
        messages = [_message("/tf", ros2_types.TF_MESSAGE, _tf(transforms))]
        messages += self._lists(stamp, bodies, faces)
        return messages

    def stop(self) -> list[RobotMessage]:
        self._humans.clear()
        return self._lists(self._stamp(), [], [])

    def persons(self) -> dict[str, str]:
        """Each tracked person now -> the crowd's id of its human (what a test checks
        the service's participants against)."""
        return {
            person: crowd_id
            for crowd_id, human in self._humans.items()
            if (person := human.person()) is not None
        }

    def _sees_face(self, human: _Human, pose: TrackedPose, dt: float) -> bool:
        toward = math.degrees(math.atan2(CAMERA_AT[1] - pose.y, CAMERA_AT[0] - pose.x))
        turned = abs((toward - pose.yaw_deg + 180.0) % 360.0 - 180.0)
        near = math.hypot(pose.x - CAMERA_AT[0], pose.y - CAMERA_AT[1]) <= FACE_RANGE_M
        limit = FACE_LOST_DEG if human.face_seen else FACE_SEEN_DEG
        human.face_seen = near and turned <= limit
        if human.face_seen:
            human.seen_s += dt
            known = self._names_given < len(KNOWN_NAMES)
            if human.name is None and human.seen_s >= RECOGNISED_S and known:
                human.name = KNOWN_NAMES[self._names_given]
                self._names_given += 1
        return human.face_seen

    def _lists(self, stamp: Time, bodies: list[str], faces: list[str]) -> list[RobotMessage]:
        """The tracked lists, between the person topics that changed: a person manager
        names a new person (and links it) before its face or body enters their list, and
        drops a person (and unlinks it) after they left theirs, so no face or body is
        ever, for one message, nobody's."""
        now = {p: h for h in self._humans.values() if (p := h.person()) is not None}
        messages = self._persons_changed(stamp, now, adding=True)
        messages += [
            _message("/humans/bodies/tracked", ros2_types.IDS_LIST, _ids(stamp, bodies)),
            _message("/humans/faces/tracked", ros2_types.IDS_LIST, _ids(stamp, faces)),
        ]
        return messages + self._persons_changed(stamp, now, adding=False)

    def _persons_changed(
        self, stamp: Time, now: dict[str, _Human], *, adding: bool
    ) -> list[RobotMessage]:
        """The links made (``adding``) or undone, and the person list grown or shrunk."""
        messages = []
        for person, human in now.items():
            for link, value in human.links().items():
                if bool(value) == adding and self._links.get((person, link), "") != value:
                    self._links[(person, link)] = value
                    topic = f"/humans/persons/{person}/{link}"
                    messages.append(_message(topic, ros2_types.STRING, _string(value), True))
        if adding:
            persons = self._persons + tuple(p for p in now if p not in self._persons)
        else:
            persons = tuple(p for p in self._persons if p in now)
        if persons != self._persons:
            self._persons = persons
            cdr = _ids(stamp, list(persons))
            messages.append(_message("/humans/persons/tracked", ros2_types.IDS_LIST, cdr, True))
        return messages

    def _stamp(self) -> Time:
        return Time.from_seconds(self.crowd.start_s + self.crowd.now)


def _message(topic: str, typename: str, message: Any, latched: bool = False) -> RobotMessage:
    return RobotMessage(topic, typename, ros2_types.serialize(message, typename), latched)


def _in_camera(stamp: Time, child: str, pose: TrackedPose, height_m: float) -> Any:
    """A person's frame (x along their heading) as the camera's tracker publishes it: in
    the optical frame."""
    half = math.radians(pose.yaw_deg) / 2.0
    offset = (pose.x - CAMERA_AT[0], pose.y - CAMERA_AT[1], height_m - CAMERA_AT[2])
    back = qinv(OPTICAL)
    rotation = qmul(back, (0.0, 0.0, math.sin(half), math.cos(half)))
    return _transform(stamp, CAMERA_FRAME, child, rotate(back, offset), rotation)


def _transform(stamp: Time, parent: str, child: str, translation: Vec, rotation: Quat) -> Any:
    new = ros2_types.message_type
    return new("geometry_msgs/msg/TransformStamped")(
        header=ros2_types.header(parent, stamp),
        child_frame_id=child,
        transform=new("geometry_msgs/msg/Transform")(
            translation=new("geometry_msgs/msg/Vector3")(*translation),
            rotation=new("geometry_msgs/msg/Quaternion")(*rotation),
        ),
    )


def _tf(transforms: list[Any]) -> Any:
    return ros2_types.message_type(ros2_types.TF_MESSAGE)(transforms=transforms)


def _ids(stamp: Time, ids: list[str]) -> Any:
    return ros2_types.message_type(ros2_types.IDS_LIST)(
        header=ros2_types.header("", stamp), ids=ids
    )


def _string(value: str) -> Any:
    return ros2_types.message_type(ros2_types.STRING)(data=value)
