"""The robot as both ROS 2 sides know it, made from the settings alone."""

from __future__ import annotations

from facing_service.config.profiles import robot_wire
from facing_service.config.settings import Settings
from facing_service.contract.robot import Distro, RosFormat
from facing_service.shell.compose import robot_for


def test_the_wire_is_where_the_settings_say_the_robots_topics_are():
    wire = robot_wire(Settings(ros_format="bridge", ros_domain_id=7, ros_namespace="/robot1/"))
    assert (wire.format, wire.domain_id, wire.namespace) == (RosFormat.BRIDGE, 7, "robot1")


def test_a_forced_distro_is_the_form_answered_in_from_the_start():
    robot = robot_for(Settings(ros_distro="humble"), answering=True)
    assert [form.distro for form in robot.form.forms] == [Distro.HUMBLE]
    learned = robot_for(Settings(), answering=False)
    assert learned.form.forms[0].distro is Distro.JAZZY  # until the robot's keys say
