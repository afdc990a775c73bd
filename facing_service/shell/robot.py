"""The robot as both ROS 2 sides know it: where its topics are (the wire) and the forms
it shows (rmw_zenoh's distro and attachment layout). The ROS 2 input learns the forms
from the robot's samples; the ROS 2 output answers in each of them. One for the service
(``compose.io_for``), shared by both sides when both speak ROS 2."""

from __future__ import annotations

from dataclasses import dataclass

from ..ros2.wire import FormLearner, Wire


@dataclass(frozen=True)
class Robot:
    """``wire``: where its topics are; ``form``: the forms it shows, learned (and, when the
    robot is answered, each answered in: ``ros2.wire.FormLearner``)."""

    wire: Wire
    form: FormLearner
