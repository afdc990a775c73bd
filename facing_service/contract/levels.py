"""Engagement levels, as hri_msgs/msg/EngagementLevel numbers them: what results carry and
consumers compare, so the contract's own (a client reads it without the engagement
machine)."""

from __future__ import annotations

from enum import IntEnum


class Level(IntEnum):
    UNKNOWN = 0
    DISENGAGED = 1
    ENGAGING = 2
    ENGAGED = 3
    DISENGAGING = 4
