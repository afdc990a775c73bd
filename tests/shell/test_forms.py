"""Where --input and --output become types: the one place that reads them."""

from __future__ import annotations

import time

import pytest

from facing_service.config.settings import Settings
from facing_service.shell.forms import forms_for
from facing_service.shell.inputs import JsonInput
from facing_service.shell.ledger import Ledger
from facing_service.shell.outputs import JsonOutput, RosTopicsOutput
from facing_service.shell.ros_input import RosInput


@pytest.mark.parametrize(
    ("given", "source", "outputs"),
    [
        ({}, JsonInput, [JsonOutput]),
        ({"input": "ros2"}, RosInput, [JsonOutput]),
        ({"output": "ros2"}, JsonInput, [JsonOutput, RosTopicsOutput]),
        ({"input": "ros2", "output": "ros2"}, RosInput, [JsonOutput, RosTopicsOutput]),
    ],
)
def test_each_setting_gives_its_types_and_our_json_keys_always(given, source, outputs):
    made, made_outputs = forms_for(Settings(**given), Ledger(time.monotonic), time.monotonic)
    assert type(made) is source and [type(o) for o in made_outputs] == outputs


def test_both_ros_sides_share_one_robot():
    """The output answers in the forms the input learns from the robot."""
    settings = Settings(input="ros2", output="ros2")
    source, (_, ros) = forms_for(settings, Ledger(time.monotonic), time.monotonic)
    assert isinstance(source, RosInput) and isinstance(ros, RosTopicsOutput)
    assert ros._robot.form is source.form
