"""ROS 2 messages for tests, built and serialized by rosbags (an independent CDR
implementation). A robot publishing them is ``rmw_zenoh.Robot``, written from rmw_zenoh's
and the bridge's sources."""

from __future__ import annotations

import math
from typing import Any

from facing_service.ros2 import types as ros2_types

S = 1_000_000_000


def _t(name: str) -> Any:
    return ros2_types.message_type(name)


def yaw_q(deg: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(math.radians(deg) / 2), math.cos(math.radians(deg) / 2))


def header(frame_id: str, stamp_ns: int) -> Any:
    stamp = _t("builtin_interfaces/msg/Time")(sec=stamp_ns // S, nanosec=stamp_ns % S)
    return _t("std_msgs/msg/Header")(stamp=stamp, frame_id=frame_id)


def transform(
    parent: str, child: str, stamp_ns: int, t=(0.0, 0.0, 0.0), q=(0.0, 0.0, 0.0, 1.0)
) -> Any:
    return _t("geometry_msgs/msg/TransformStamped")(
        header=header(parent, stamp_ns),
        child_frame_id=child,
        transform=_t("geometry_msgs/msg/Transform")(
            translation=_t("geometry_msgs/msg/Vector3")(x=t[0], y=t[1], z=t[2]),
            rotation=_t("geometry_msgs/msg/Quaternion")(x=q[0], y=q[1], z=q[2], w=q[3]),
        ),
    )


def tf_message(*transforms: Any) -> bytes:
    message = _t(ros2_types.TF_MESSAGE)(transforms=list(transforms))
    return ros2_types.serialize(message, ros2_types.TF_MESSAGE)


def ids_list(ids: list[str], stamp_ns: int = 0) -> bytes:
    message = _t(ros2_types.IDS_LIST)(header=header("", stamp_ns), ids=ids)
    return ros2_types.serialize(message, ros2_types.IDS_LIST)


def string(data: str) -> bytes:
    return ros2_types.serialize(_t(ros2_types.STRING)(data=data), ros2_types.STRING)


TYPES = {
    "/tf": ros2_types.TF_MESSAGE,
    "/tf_static": ros2_types.TF_MESSAGE,
    "/humans/bodies/tracked": ros2_types.IDS_LIST,
    "/humans/faces/tracked": ros2_types.IDS_LIST,
    "/humans/persons/tracked": ros2_types.IDS_LIST,
}


def type_of(topic: str) -> str:
    return TYPES.get(topic, ros2_types.STRING)
