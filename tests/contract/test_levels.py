"""Engagement levels are hri_msgs' own numbers: checked against the pinned upstream
EngagementLevel.msg (its git blob is checked against hri_msgs 2.0.0 in tests/ros2)."""

from __future__ import annotations

import re

from facing_service.contract.levels import Level
from facing_service.ros2.output import ENGAGEMENT_LEVEL

from upstream import definition


def test_each_level_is_numbered_as_hri_msgs_numbers_it():
    said = dict(re.findall(r"^uint8 ([A-Z]+)=(\d+)", definition(ENGAGEMENT_LEVEL), re.M))
    assert {name: int(value) for name, value in said.items()} == {
        level.name: level.value for level in Level
    }
