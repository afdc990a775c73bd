"""Engagement levels are hri_msgs' own numbers: checked against the pinned upstream
EngagementLevel.msg (its git blob is checked against hri_msgs 2.0.0 in tests/ros2)."""

from __future__ import annotations

import json
import re

import pytest
from pydantic import ValidationError

from facing_service.contract.levels import Level
from facing_service.contract.schemas import EngagementEvent
from facing_service.ros2.output import ENGAGEMENT_LEVEL

from upstream import definition


def test_each_level_is_numbered_as_hri_msgs_numbers_it():
    said = dict(re.findall(r"^uint8 ([A-Z]+)=(\d+)", definition(ENGAGEMENT_LEVEL), re.M))
    assert {name: int(value) for name, value in said.items()} == {
        level.name: level.value for level in Level
    }


def test_a_level_prints_as_its_name_and_is_made_from_it():
    """A defect found: ``str(Level.ENGAGED)`` printed ``3`` on Python 3.11, ``Level("ENGAGED")``
    raised."""
    assert str(Level.ENGAGED) == f"{Level.ENGAGED}" == "ENGAGED"
    assert f"{Level.ENGAGING:>10}" == "  ENGAGING"
    assert Level("ENGAGED") is Level(3) is Level["ENGAGED"] is Level.ENGAGED
    with pytest.raises(ValueError):
        Level("engaged ")


def test_a_level_compares_as_its_number_and_still_equals_its_name():
    """Code written when a callback's ``event.level`` was the string keeps its meaning."""
    assert Level.ENGAGED == 3 and Level.ENGAGED == "ENGAGED"
    assert "ENGAGED" == Level.ENGAGED  # noqa: SIM300 (the string on the left, on purpose)
    assert Level.ENGAGED != "DISENGAGED" and Level.ENGAGED != 1
    assert Level.DISENGAGED < Level.ENGAGED
    # a defect found: it hashed as its number, so the string code it keeps the meaning of failed
    assert Level.ENGAGED in {"ENGAGED", "ENGAGING"} and Level.ENGAGED not in {"DISENGAGED"}
    assert {"ENGAGED": "x"}.get(Level.ENGAGED) == "x" and {Level.ENGAGED: "x"}["ENGAGED"] == "x"
    assert {Level.ENGAGED: "x"}[Level(3)] == "x" and {3: "x"}[int(Level.ENGAGED)] == "x"
    assert f"{Level.ENGAGED:d}" == "3" and f"{Level.ENGAGED:02d}" == "03"


def test_a_wire_model_reads_the_name_and_hands_out_a_level():
    """A defect found: in ``on_engaged``, ``event.level == Level.ENGAGED`` was False (a str)."""
    said = {
        "body_id": "anna", "frame_id": "base_link", "stamp": {"sec": 1, "nanosec": 0},
        "previous": "ENGAGING", "level": "ENGAGED", "level_value": 3, "score": 0.9,
        "zone": "social",
    }  # fmt: skip
    event = EngagementEvent.model_validate_json(json.dumps(said))
    assert event.level is Level.ENGAGED and event.previous is Level.ENGAGING
    assert json.loads(event.model_dump_json())["level"] == "ENGAGED"  # the wire: its name
    with pytest.raises(ValidationError):
        EngagementEvent.model_validate_json(json.dumps({**said, "level": "ENGAGD"}))
