"""facing-service: which tracked bodies are oriented toward the robot, over zenoh."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("facing-service")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0+unknown"

from .client import FacingClient
from .contract import (
    BodyRef,
    EngagementEvent,
    EngagementState,
    FacingState,
    FrameFacing,
    GazePair,
    GroupState,
    ServiceStatus,
)
from .errors import ClientNotOpen, FacingError, QueryRefused, SettingsError, UnknownFrame

__all__ = [
    "BodyRef",
    "ClientNotOpen",
    "EngagementEvent",
    "EngagementState",
    "FacingClient",
    "FacingError",
    "FacingState",
    "FrameFacing",
    "GazePair",
    "GroupState",
    "QueryRefused",
    "ServiceStatus",
    "SettingsError",
    "UnknownFrame",
    "__version__",
]
