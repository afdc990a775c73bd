"""facing-service: which tracked bodies are oriented toward the robot, over zenoh.

The public names are loaded when first used (PEP 562): the command line's entry point
imports this package before it can catch Ctrl-C, and the client's imports (zenoh, numpy)
took ~0.3 s in which a Ctrl-C printed a traceback."""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .client import AsyncFacingClient, ClientOptions, FacingClient
    from .config.version import VERSION as __version__
    from .contract import (
        BodyRef,
        EngagementEvent,
        EngagementState,
        FacingState,
        FrameFacing,
        GazePair,
        Greeting,
        GroupState,
        Place,
        ServiceStatus,
    )
    from .contract.levels import Level
    from .errors import (
        ClientNotOpen,
        FacingError,
        NoService,
        QueryRefused,
        SettingsError,
        UnknownFrame,
    )

#: Where each public name lives.
_HOMES = {
    "__version__": ".config.version",
    "AsyncFacingClient": ".client",
    "ClientOptions": ".client",
    "FacingClient": ".client",
    "Level": ".contract.levels",
    **dict.fromkeys(
        ["BodyRef", "EngagementEvent", "EngagementState", "FacingState", "FrameFacing",
         "GazePair", "Greeting", "GroupState", "Place", "ServiceStatus"],
        ".contract",
    ),
    **dict.fromkeys(
        ["ClientNotOpen", "FacingError", "NoService", "QueryRefused", "SettingsError",
         "UnknownFrame"],
        ".errors",
    ),
}  # fmt: skip


def __getattr__(name: str) -> Any:
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    home = importlib.import_module(_HOMES[name], __name__)
    value = getattr(home, "VERSION" if name == "__version__" else name)
    globals()[name] = value
    return value


__all__ = [
    "AsyncFacingClient",
    "BodyRef",
    "ClientNotOpen",
    "ClientOptions",
    "EngagementEvent",
    "EngagementState",
    "FacingClient",
    "FacingError",
    "FacingState",
    "FrameFacing",
    "GazePair",
    "Greeting",
    "GroupState",
    "Level",
    "NoService",
    "Place",
    "QueryRefused",
    "ServiceStatus",
    "SettingsError",
    "UnknownFrame",
    "__version__",
]
