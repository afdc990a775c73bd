"""What the service decides, drawn for RViz (``--output ros2``): a
``visualization_msgs/MarkerArray`` on ``/humans/facing/markers`` in the base frame.

Per person (namespace ``person/<id>``, stable ids): 0 the facing cone (a triangle fan at
the threshold, 1.5 m long), 1 an arrow along the body's or head's heading, 2 a text label
(id, level, angle, distance); coloured by level: ENGAGED green, ENGAGING and DISENGAGING
amber, DISENGAGED red, UNKNOWN grey. Per group (``group/<id>``): 0 its o-space (a circle
at its centre), 1 lines from the centre to its members (to the robot's origin too when
it is one), 2 an arrow where the robot should stand to join it, pointing into the group.
Per person engaging in no group (``greet/<id>``): 0 an arrow where the robot should stand
to greet them, pointing at them. Whatever was drawn and is gone is DELETEd by its
(namespace, id), so people who leave vanish at once; every marker also has a lifetime, so
a service that stops leaves nothing behind. Pure: messages from plain data.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..contract.levels import Level
from ..contract.poses import Pose
from ..contract.stamps import ZERO, Time
from ..core.snapshot import TurnSnapshot
from ..core.social.groups import Group
from ..core.social.join import JoinPose
from ..core.social.scene import ROBOT, PlaceToGreet
from . import types as ros2_types

MARKER_ARRAY = "visualization_msgs/msg/MarkerArray"
MARKERS_TOPIC = "/humans/facing/markers"
CONE_LENGTH_M = 1.5
CONE_STEPS = 8  # triangles in a cone's fan
CIRCLE_STEPS = 24
GROUP_RADIUS_M = 0.3
LIFETIME_S = 2  # every marker vanishes this long after its last update
COLOURS = {
    Level.ENGAGED: (0.1, 0.8, 0.1),
    Level.ENGAGING: (1.0, 0.75, 0.0),
    Level.DISENGAGING: (1.0, 0.75, 0.0),
    Level.DISENGAGED: (0.9, 0.1, 0.1),
    Level.UNKNOWN: (0.6, 0.6, 0.6),
}
GROUP_COLOUR = (0.8, 0.2, 0.8)
PLACE_COLOUR = (0.1, 0.5, 1.0)  # where the robot should stand


@dataclass(frozen=True, slots=True)
class PersonMarker:
    """One person as drawn: where, which way, how engaged, the facing figures."""

    id: str
    translation: tuple[float, float, float]
    rotation: tuple[float, float, float, float]
    level: Level
    threshold_deg: float
    angle_deg: float | None
    distance_m: float | None


def drawn(snapshot: TurnSnapshot) -> dict[str, list[PersonMarker]]:
    """Every tracked person as the markers draw them, by frame."""
    levels = snapshot.levels
    poses: dict[str, dict[str, Pose]] = {}
    out: dict[str, list[PersonMarker]] = {}
    for s in snapshot.states:
        if s.frame_id not in poses:
            poses[s.frame_id] = dict(snapshot.poses(s.frame_id))
        pose = poses[s.frame_id][s.body_id]
        out.setdefault(s.frame_id, []).append(
            PersonMarker(s.body_id, pose.translation, pose.rotation,
                  levels.get(s.body, Level.UNKNOWN), s.threshold_deg, s.angle_deg,
                  s.distance_m)
        )  # fmt: skip
    return out


def _t(name: str) -> Any:
    return ros2_types.message_type(name)


def _point(x: float, y: float, z: float = 0.0) -> Any:
    return _t("geometry_msgs/msg/Point")(x=x, y=y, z=z)


def _marker(
    frame: str,
    stamp: Time,
    ns: str,
    mid: int,
    kind: int,
    *,
    action: int = 0,  # Marker.ADD
    pose: Any = None,
    points: list[Any] | None = None,
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0),
    colour: tuple[float, float, float] = (1.0, 1.0, 1.0),
    alpha: float = 1.0,
    text: str = "",
) -> Any:
    """One marker; the fields RViz does not use here (textures, meshes) empty."""
    return _t("visualization_msgs/msg/Marker")(
        header=ros2_types.header(frame, stamp),
        ns=ns,
        id=mid,
        type=kind,
        action=action,
        pose=pose if pose is not None else _pose((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
        scale=_t("geometry_msgs/msg/Vector3")(*scale),
        color=_t("std_msgs/msg/ColorRGBA")(*colour, alpha),
        lifetime=_t("builtin_interfaces/msg/Duration")(sec=LIFETIME_S, nanosec=0),
        frame_locked=False,
        points=points or [],
        colors=[],
        texture_resource="",
        texture=_t("sensor_msgs/msg/CompressedImage")(
            header=ros2_types.header("", ZERO), format="", data=np.zeros(0, dtype=np.uint8)
        ),
        uv_coordinates=[],
        text=text,
        mesh_resource="",
        mesh_file=_t("visualization_msgs/msg/MeshFile")(
            filename="", data=np.zeros(0, dtype=np.uint8)
        ),
        mesh_use_embedded_materials=False,
    )


def _pose(t: tuple[float, float, float], q: tuple[float, float, float, float]) -> Any:
    return _t("geometry_msgs/msg/Pose")(
        position=_point(*t), orientation=_t("geometry_msgs/msg/Quaternion")(*q)
    )


def person_markers(frame: str, stamp: Time, p: PersonMarker) -> list[Any]:
    """The cone, the arrow and the label of one person, in the person's frame pose."""
    m = _t("visualization_msgs/msg/Marker")
    colour, ns, pose = COLOURS[p.level], f"person/{p.id}", _pose(p.translation, p.rotation)
    half = math.radians(p.threshold_deg)
    fan = []
    for k in range(CONE_STEPS):
        a, b = (-half + 2 * half * i / CONE_STEPS for i in (k, k + 1))
        fan += [
            _point(0.0, 0.0),
            _point(CONE_LENGTH_M * math.cos(a), CONE_LENGTH_M * math.sin(a)),
            _point(CONE_LENGTH_M * math.cos(b), CONE_LENGTH_M * math.sin(b)),
        ]
    angle = "-" if p.angle_deg is None else f"{p.angle_deg:.0f}°"
    distance = "-" if p.distance_m is None else f"{p.distance_m:.1f} m"
    x, y, z = p.translation
    return [
        _marker(frame, stamp, ns, 0, m.TRIANGLE_LIST, pose=pose, points=fan, colour=colour,
                alpha=0.3),
        _marker(frame, stamp, ns, 1, m.ARROW, pose=pose, points=[_point(0, 0), _point(0.6, 0)],
                scale=(0.05, 0.1, 0.1), colour=colour),
        _marker(frame, stamp, ns, 2, m.TEXT_VIEW_FACING, pose=_pose((x, y, z + 0.4),
                (0.0, 0.0, 0.0, 1.0)), scale=(0.15, 0.15, 0.15), colour=colour,
                text=f"{p.id} {p.level.name} {angle} {distance}"),
    ]  # fmt: skip


def group_markers(
    frame: str, stamp: Time, group: Group, where: dict[str, tuple[float, float]]
) -> list[Any]:
    """A group's o-space circle and the lines to its members (the robot at the origin)."""
    m = _t("visualization_msgs/msg/Marker")
    cx, cy = group.centre
    circle = [
        _point(cx + GROUP_RADIUS_M * math.cos(a), cy + GROUP_RADIUS_M * math.sin(a))
        for a in (2 * math.pi * i / CIRCLE_STEPS for i in range(CIRCLE_STEPS + 1))
    ]
    lines = []
    for member in sorted(group.members):
        x, y = (0.0, 0.0) if member == ROBOT else where.get(member, (cx, cy))
        lines += [_point(cx, cy), _point(x, y)]
    ns = f"group/{group.id}"
    drawn = [
        _marker(frame, stamp, ns, 0, m.LINE_STRIP, points=circle, scale=(0.04, 0, 0),
                colour=GROUP_COLOUR),
        _marker(frame, stamp, ns, 1, m.LINE_LIST, points=lines, scale=(0.02, 0, 0),
                colour=GROUP_COLOUR, alpha=0.7),
    ]  # fmt: skip
    if group.join is not None:  # (None with the robot in the group)
        drawn.append(place_marker(frame, stamp, ns, 2, group.join))
    return drawn


def place_marker(frame: str, stamp: Time, ns: str, mid: int, place: JoinPose) -> Any:
    """Where the robot should stand: an arrow at the place, along the way to face."""
    m = _t("visualization_msgs/msg/Marker")
    return _marker(frame, stamp, ns, mid, m.ARROW, pose=place_pose(place),
                   scale=(0.5, 0.08, 0.08), colour=PLACE_COLOUR)  # fmt: skip


def place_pose(place: JoinPose) -> Any:
    """A place as a ``geometry_msgs/Pose`` on the floor (yaw about z)."""
    half = place.yaw / 2
    return _pose((place.x, place.y, 0.0), (0.0, 0.0, math.sin(half), math.cos(half)))


def deletion(frame: str, stamp: Time, ns: str, mid: int) -> Any:
    m = _t("visualization_msgs/msg/Marker")
    return _marker(frame, stamp, ns, mid, m.ARROW, action=m.DELETE)


class MarkerDrawer:
    """The markers of each turn, and the DELETEs of what was drawn before and is gone."""

    def __init__(self) -> None:
        self._drawn: set[tuple[str, int]] = set()

    def draw(
        self,
        frame: str,
        stamp: Time,
        people: Sequence[PersonMarker],
        groups: Sequence[Group],
        greetings: Sequence[PlaceToGreet] = (),
    ) -> bytes:
        where = {p.id: (p.translation[0], p.translation[1]) for p in people}
        markers = [mk for p in people for mk in person_markers(frame, stamp, p)]
        markers += [mk for g in groups for mk in group_markers(frame, stamp, g, where)]
        markers += [place_marker(frame, stamp, f"greet/{g.body_id}", 0, g.pose) for g in greetings]
        now = {(mk.ns, mk.id) for mk in markers}
        markers += [deletion(frame, stamp, ns, mid) for ns, mid in sorted(self._drawn - now)]
        self._drawn = now
        array = _t(MARKER_ARRAY)(markers=markers)
        return ros2_types.serialize(array, MARKER_ARRAY)
