"""The robot as both ROS 2 sides know it: where its topics are (the wire) and the forms
it shows (rmw_zenoh's distro and attachment layout). The ROS 2 input learns the forms
from the robot's samples; the ROS 2 output answers in each of them. One for the service
(``forms.forms_for``), shared by both sides when both speak ROS 2."""

from __future__ import annotations

from dataclasses import dataclass

from ..config.settings import Settings
from ..contract.robot import Distro, RosFormat
from ..ros2.wire import FormLearner, Wire


def robot_wire(settings: Settings) -> Wire:
    """Where the robot's topics are on zenoh, and the form we write in before (or instead
    of) learning the robot's."""
    return Wire(
        RosFormat(settings.ros_format),
        settings.ros_domain_id,
        settings.ros_namespace,
        settings.forced_distro or Distro.JAZZY,
    )


@dataclass(frozen=True)
class Robot:
    wire: Wire
    form: FormLearner

    @classmethod
    def of(cls, settings: Settings, answering: bool) -> Robot:
        """``answering``: whether the robot is answered on its topics (then every form it
        shows is answered in, see ``ros2.wire.FormLearner``)."""
        return cls(robot_wire(settings), FormLearner(settings.forced_distro, answering=answering))
