"""The wire contract: the key spaces (``keys``) and the JSON payloads (``schemas``) that
trackers, consumers and the service agree on. Pure; imports nothing of the package."""

from .keys import BodyRef
from .poses import Rejection
from .schemas import (
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

__all__ = [
    "BodyRef",
    "EngagementEvent",
    "EngagementState",
    "FacingState",
    "FrameFacing",
    "GazePair",
    "Greeting",
    "GroupState",
    "Place",
    "Rejection",
    "ServiceStatus",
]
