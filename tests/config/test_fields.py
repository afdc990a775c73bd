"""How a setting is declared and the session checks shared by the service's settings and
a client's options (config/fields)."""

from __future__ import annotations

import pytest
from pydantic import Field, ValidationError

from facing_service.config.fields import ROS_IN, SessionChecks, flag


class Session(SessionChecks):
    namespace: str = "hri"
    connect: list[str] = Field(default_factory=list)
    listen: list[str] = Field(default_factory=list)
    cfg: list[str] = Field(default_factory=list)
    reconnect_s: list[float] = Field(default_factory=lambda: [1.0, 4.0])
    wait_s: float = flag(0.25, "how long", ROS_IN, ge=0, le=5)


def test_a_flag_carries_its_help_group_and_bounds():
    field = Session.model_fields["wait_s"]
    assert field.default == 0.25 and field.description == "how long"
    assert field.json_schema_extra["group"] == ROS_IN
    with pytest.raises(ValidationError, match="less than or equal to 5"):
        Session(wait_s=6)


@pytest.mark.parametrize(
    ("given", "said"),
    [
        ({"namespace": "a/*"}, "namespace"),
        ({"connect": ["tcp/nowhere"]}, "tcp/nowhere"),
        ({"cfg": ["novalue"]}, "entry 1 is not KEY:VALUE"),
        ({"reconnect_s": [5.0, 1.0]}, "0 < FIRST <= MOST <= 60"),
    ],
)
def test_what_a_session_is_made_from_is_checked_in_one_line(given, said):
    with pytest.raises(ValidationError, match=said):
        Session(**given)
