"""The live page's model (``client.view.snapshot``) as Foxglove scene entities: the same
data the page draws, for Foxglove's 3D panel, in the base frame.

- each person ``person/<id>``: a cylinder where they stand, an arrow along their heading,
  their facing cone (two rays at their threshold, 1.5 m long) and a label (id, level),
  coloured by level as the page colours them;
- each group ``group/<id>``: its o-space centre, a line to each member (and to the robot
  when it is in the group), and an arrow where the robot should stand to join;
- ``greet/<id>``: where the robot should stand to greet a person in no group;
- ``gaze/<sender>/<receiver>``: who faces whom (a line; the robot is ``robot``);
- ``robot``: a box at the base frame's origin, x forward.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from foxglove.messages import (
    ArrowPrimitive,
    Color,
    CubePrimitive,
    CylinderPrimitive,
    FrameTransform,
    LinePrimitive,
    LinePrimitiveLineType,
    Point3,
    Pose,
    Quaternion,
    SceneEntity,
    SceneEntityDeletion,
    SceneEntityDeletionType,
    SceneUpdate,
    TextPrimitive,
    Timestamp,
    Vector3,
)

#: The page's palette, by level.
PALETTE = {
    "ENGAGED": (0.13, 0.67, 0.13),
    "ENGAGING": (0.9, 0.66, 0.0),
    "DISENGAGING": (0.9, 0.66, 0.0),
    "DISENGAGED": (0.87, 0.13, 0.13),
    "UNKNOWN": (0.6, 0.6, 0.6),
}
GROUP = (0.7, 0.2, 0.7)
PLACE = (0.1, 0.5, 1.0)
CONE_M = 1.5


def _colour(rgb: tuple[float, float, float], a: float = 1.0) -> Color:
    return Color(r=rgb[0], g=rgb[1], b=rgb[2], a=a)


def _yaw(yaw: float) -> Quaternion:
    return Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2.0), w=math.cos(yaw / 2.0))


def _pose(x: float, y: float, z: float = 0.0, yaw: float = 0.0) -> Pose:
    return Pose(position=Vector3(x=x, y=y, z=z), orientation=_yaw(yaw))


def _arrow(x: float, y: float, yaw: float, rgb: tuple[float, float, float]) -> ArrowPrimitive:
    return ArrowPrimitive(pose=_pose(x, y, 0.05, yaw), shaft_length=0.5, shaft_diameter=0.06,
                          head_length=0.2, head_diameter=0.15, color=_colour(rgb))  # fmt: skip


RGB = tuple[float, float, float]


def _line(
    points: Sequence[tuple[float, float]],
    rgb: RGB,
    kind: LinePrimitiveLineType = LinePrimitiveLineType.LineStrip,
) -> LinePrimitive:
    return LinePrimitive(type=kind, pose=_pose(0.0, 0.0), thickness=0.03, scale_invariant=False,
                         points=[Point3(x=x, y=y, z=0.05) for x, y in points],
                         color=_colour(rgb))  # fmt: skip


def person(p: Mapping[str, Any], frame: str, stamp: Timestamp) -> SceneEntity:
    """A person of the page's model, as the page draws them."""
    rgb = PALETTE.get(p["level"], PALETTE["UNKNOWN"])
    x, y, heading = p["x"], p["y"], math.radians(p["heading_deg"])
    half = math.radians(p["threshold_deg"])
    rays = [(x + CONE_M * math.cos(heading + s * half), y + CONE_M * math.sin(heading + s * half))
            for s in (1.0, -1.0)]  # fmt: skip
    facing = "facing" if p["facing"] else "not facing"
    return SceneEntity(
        timestamp=stamp, frame_id=frame, id=f"person/{p['id']}",
        cylinders=[CylinderPrimitive(pose=_pose(x, y, 0.85), size=Vector3(x=0.4, y=0.4, z=1.7),
                                     color=_colour(rgb, 0.6))],
        arrows=[ArrowPrimitive(pose=_pose(x, y, 1.0, heading), shaft_length=0.6,
                               shaft_diameter=0.05, head_length=0.2, head_diameter=0.12,
                               color=_colour(rgb))],
        lines=[_line([rays[0], (x, y), rays[1]], rgb)],
        texts=[TextPrimitive(pose=_pose(x, y, 2.0), billboard=True, font_size=14.0,
                             scale_invariant=True, color=_colour((1.0, 1.0, 1.0)),
                             text=f"{p['id']} {p['level']} ({facing})")],
    )  # fmt: skip


def entities(model: Mapping[str, Any], stamp: Timestamp) -> dict[str, SceneEntity]:
    """Every entity of the page's model (``snapshot``), in its frame, by id."""
    frame = model["frame"]
    where = {p["id"]: (p["x"], p["y"]) for p in model["people"]}
    where[""] = (0.0, 0.0)  # the robot, in who faces whom
    out: dict[str, SceneEntity] = {}

    def add(id_: str, **primitives: Any) -> None:
        out[id_] = SceneEntity(timestamp=stamp, frame_id=frame, id=id_, **primitives)

    add("robot", cubes=[CubePrimitive(pose=_pose(0.0, 0.0, 0.3), size=Vector3(x=0.5, y=0.4, z=0.6),
                                      color=_colour((0.2, 0.2, 0.3)))],
        arrows=[_arrow(0.0, 0.0, 0.0, (0.2, 0.2, 0.3))])  # fmt: skip
    for p in model["people"]:
        out[f"person/{p['id']}"] = person(p, frame, stamp)
    for g in model["groups"]:
        centre = (g["centre"]["x"], g["centre"]["y"])
        ends = [where[m] for m in g["members"] if m in where] + ([(0.0, 0.0)] if g["robot"] else [])
        join = g.get("join")
        arrows = [] if not join else [_arrow(join["x"], join["y"], join["yaw"], PLACE)]
        lines = [_line([centre, end], GROUP, LinePrimitiveLineType.LineList) for end in ends]
        add(f"group/{g['id']}", arrows=arrows, lines=lines)
    for greeting in model["greetings"]:
        place = greeting["place"]
        add(f"greet/{greeting['body_id']}",
            arrows=[_arrow(place["x"], place["y"], place["yaw"], PLACE)])  # fmt: skip
    for pair in model["gazing"]:  # (the model's pairs are between people it shows)
        ends = [where[pair["sender"]], where[pair["receiver"]]]
        add(f"gaze/{pair['sender'] or 'robot'}/{pair['receiver'] or 'robot'}",
            lines=[_line(ends, (0.3, 0.3, 0.3))])  # fmt: skip
    return out


def update(
    model: Mapping[str, Any], before: set[str], stamp: Timestamp
) -> tuple[SceneUpdate, set[str]]:
    """The scene now, with a deletion for each entity of ``before`` no longer in it (a
    person who left); and the ids it holds."""
    now = entities(model, stamp)
    gone = [SceneEntityDeletion(timestamp=stamp, type=SceneEntityDeletionType.MatchingId, id=i)
            for i in sorted(before - now.keys())]  # fmt: skip
    return SceneUpdate(deletions=gone, entities=list(now.values())), set(now)


def transforms(model: Mapping[str, Any], stamp: Timestamp) -> list[FrameTransform]:
    """Each person's frame (``facing/<id>``, x along their heading) under the base frame:
    a transform tree a user can put beside their own."""
    return [
        FrameTransform(timestamp=stamp, parent_frame_id=model["frame"],
                       child_frame_id=f"facing/{p['id']}",
                       translation=Vector3(x=p["x"], y=p["y"], z=0.0),
                       rotation=_yaw(math.radians(p["heading_deg"])))
        for p in model["people"]
    ]  # fmt: skip
