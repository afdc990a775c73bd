"""How a setting is declared (``flag``: its field, help, group and flag form together),
the groups the help and the docs list them under, and the checks of what a zenoh session
is made from, shared by the service's settings and a client's options."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from pydantic import BaseModel, Field, field_validator
from pydantic.json_schema import JsonDict

from ..contract import keys
from .disclosure import public_endpoint
from .endpoints import endpoint_problem

SERVICE, ENGAGEMENT, HEADS = "service", "engagement levels", "heads: face frames, from ROS 2 input"
GROUPS = "groups: who faces whom, F-formations"
ROS_IN = "ROS 2 input: a robot's own /tf and /humans/* topics"
ROS_OUT = "ROS 2 output: our results on the robot's own topics, beside the JSON keys"
ZENOH = "zenoh session"


def flag(
    default: Any,
    description: str,
    group: str = SERVICE,
    *,
    short: str | None = None,
    metavar: str | None = None,
    shown: str | None = None,
    default_factory: Callable[[], Any] | None = None,
    **constraints: Any,
) -> Any:
    """A setting's field with its flag: its help (the description), group, short form,
    metavar, and the default as the docs say it when the value itself would not
    (``shown``). One call, so that type checkers see a plain default."""
    extra: JsonDict = {"group": group, "short": short, "metavar": metavar, "shown": shown}
    if default_factory is not None:
        return Field(default_factory=default_factory, description=description,
                     json_schema_extra=extra, **constraints)  # fmt: skip
    return Field(default, description=description, json_schema_extra=extra, **constraints)


class SessionChecks(BaseModel):
    """The checks of what a zenoh session is made from, one for the service's
    ``Settings`` and a client's ``ClientOptions`` alike (each declares the fields)."""

    @field_validator("namespace", check_fields=False)
    @classmethod
    def _namespace(cls, value: str) -> str:
        return keys.validate_namespace(value)

    @field_validator("base_frame", "frame", check_fields=False)
    @classmethod
    def _frame(cls, value: str) -> str:
        return keys.validate_frame_filter(value)

    @field_validator("connect", "listen", check_fields=False)
    @classmethod
    def _endpoints(cls, value: list[str], info: Any) -> list[str]:
        for endpoint in value:
            if reason := endpoint_problem(endpoint, listen=info.field_name == "listen"):
                raise ValueError(f"{public_endpoint(endpoint)}: {reason}")
        return value

    @field_validator("reconnect_s", check_fields=False)
    @classmethod
    def _reconnect(cls, value: list[float]) -> list[float]:
        if len(value) != 2 or not 0 < value[0] <= value[1] <= 60:
            raise ValueError("reconnect_s is FIRST,MOST seconds, 0 < FIRST <= MOST <= 60")
        return value

    @field_validator("cfg", check_fields=False)
    @classmethod
    def _cfg(cls, value: list[str]) -> list[str]:
        for position, entry in enumerate(value, 1):
            key, sep, _ = entry.partition(":")
            if not (sep and key):  # the entry itself is not quoted: it may be a secret
                raise ValueError(f"entry {position} is not KEY:VALUE")
        return value
