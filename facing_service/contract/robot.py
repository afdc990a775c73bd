"""What a user says about the robot, and the bounds on what it may send: read by the
settings, the ROS 2 adapter and the TF buffer alike, so none of them imports another for
a constant (and ``FacingClient``, which reads settings, loads none of them)."""

from __future__ import annotations

from enum import Enum


class RosFormat(str, Enum):
    """How the robot's topics reach zenoh (``--ros-format``; see ``ros2.wire``)."""

    RMW_ZENOH = "rmw_zenoh"
    BRIDGE = "bridge"


class Distro(str, Enum):
    """Which form of rmw_zenoh's keys a robot uses: what its type hash chunk says."""

    HUMBLE = "humble"  # TypeHashNotSupported
    JAZZY = "jazzy"  # RIHS01_<sha256>: Jazzy, Kilted, Rolling

    def describe(self) -> str:
        if self is Distro.HUMBLE:
            return "Humble (keys carry TypeHashNotSupported)"
        return "Jazzy or later (keys carry RIHS01 type hashes)"


#: A robot's message larger than this is refused undecoded (``--ros-max-message-bytes``).
DEFAULT_MAX_MESSAGE_BYTES = 1 << 20
#: Most frames a TF buffer names (``--ros-max-frames``): tf2 never forgets a frame, so a
#: robot naming new frames without end (400 000 took 517 MB) would grow it without bound.
DEFAULT_MAX_FRAMES = 10_000
