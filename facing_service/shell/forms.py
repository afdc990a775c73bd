"""The one place where ``--input`` and ``--output`` become types: everything after works
with an ``inputs.Input`` and a list of ``outputs.Output``, never with the setting."""

from __future__ import annotations

from collections.abc import Callable

from ..config.settings import Settings
from .inputs import Input, JsonInput
from .ledger import Ledger
from .outputs import JsonOutput, Output, RosTopicsOutput
from .robot import Robot
from .ros_input import RosInput


def forms_for(
    settings: Settings, ledger: Ledger, clock: Callable[[], float]
) -> tuple[Input, list[Output]]:
    """The input, and the outputs (our JSON keys always; the robot's topics with
    ``--output ros2``). One ``Robot`` is shared when both sides speak ROS 2: the output
    answers in the forms the input learns."""
    answering = settings.output == "ros2"
    robot = Robot.of(settings, answering)
    source: Input = (
        RosInput(settings, robot, ledger, clock)
        if settings.input == "ros2"
        else JsonInput(settings, ledger)
    )
    outputs: list[Output] = [JsonOutput(settings)]
    if answering:
        outputs.append(RosTopicsOutput(settings, robot))
    return source, outputs
