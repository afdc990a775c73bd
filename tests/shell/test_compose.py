"""The composition root: the service's parts built from the settings, each given what it
uses; --input and --output become types there, the one place that reads them."""

from __future__ import annotations

import time

import pytest

from facing_service.config.settings import Settings
from facing_service.shell.compose import io_for, parts_for
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
    made, made_outputs = io_for(Settings(**given), Ledger(time.monotonic), time.monotonic)
    assert type(made) is source and [type(o) for o in made_outputs] == outputs


def test_both_ros_sides_share_one_robot():
    """The output answers in the forms the input learns from the robot."""
    settings = Settings(input="ros2", output="ros2")
    source, (_, ros) = io_for(settings, Ledger(time.monotonic), time.monotonic)
    assert isinstance(source, RosInput) and isinstance(ros, RosTopicsOutput)
    assert ros._robot.form is source.form


def test_the_parts_are_what_the_settings_say_and_nothing_below_reads_them():
    settings = Settings(base_frame="cam", max_bodies=7, threshold_deg=25.0)
    parts = parts_for(settings, Ledger(time.monotonic), time.monotonic)
    assert parts.tracker.max_bodies == 7 and parts.tracker.frames()[0].frame_id == "cam"
    assert parts.source.hot_key() == "hri/bodies/*/pose/cam"
    assert parts.scenes is not None and [type(o) for o in parts.outputs] == [JsonOutput]
