"""facing-service: which tracked bodies are oriented toward the robot, over zenoh."""

from .client import ClientOptions, FacingClient
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

__all__ = [
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
