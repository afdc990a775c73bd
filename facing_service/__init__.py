"""facing-service: which tracked bodies are oriented toward the robot, over zenoh."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("facing-service")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0+unknown"

from .client import ClientOptions, FacingClient
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
