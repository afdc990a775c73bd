"""Engagement levels, as hri_msgs/msg/EngagementLevel numbers them: what results carry and
consumers compare, so the contract's own (a client reads it without the engagement
machine).

One type wherever a level is handed out (a callback's ``event.level`` was the
string ``"ENGAGED"``, ``engagement()`` gave ``Level``): it orders and compares as hri_msgs'
number, prints as its name (an IntEnum's ``str()`` is the number from Python 3.11 on), is
made from either (``Level("ENGAGED") is Level(3) is Level.ENGAGED``), and still equals its
name, so code written when ``event.level`` was a string keeps its meaning instead of
silently comparing False. On the wire it is the name.

Equal to both its number and its name, it can hash as only one: it hashes as its name
(``level in {"ENGAGED", "ENGAGING"}`` was False and ``{"ENGAGED": ...}.get(level)``
None, where the string code it promises to keep meant True), so a set or dict keyed by
names finds it, as one keyed by levels does; one keyed by bare numbers does not (compare
with ``int(level)`` there). Formatted with a number's spec (``{level:d}``) it is its
number, else its name.
"""

from __future__ import annotations

from enum import IntEnum
from typing import Annotated

from pydantic import PlainSerializer, WithJsonSchema


class Level(IntEnum):
    UNKNOWN = 0
    DISENGAGED = 1
    ENGAGING = 2
    ENGAGED = 3
    DISENGAGING = 4

    def __str__(self) -> str:
        return self.name

    def __format__(self, spec: str) -> str:
        if spec and spec[-1] in "bcdoxXn":  # a number's format: hri_msgs' number
            return int.__format__(self, spec)
        return format(self.name, spec)

    def __eq__(self, other: object) -> bool:
        return self.name == other if isinstance(other, str) else int.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash(self.name)

    @classmethod
    def _missing_(cls, value: object) -> Level | None:
        """A level's name is a level too (what the wire and hri_msgs' docs say)."""
        return cls.__members__.get(value) if isinstance(value, str) else None


#: A level in a wire model: its name in JSON (as the service sends it), a ``Level`` in Python.
LevelName = Annotated[
    Level,
    PlainSerializer(lambda level: level.name, return_type=str, when_used="json"),
    WithJsonSchema({"enum": [level.name for level in Level], "type": "string"}),
]
