"""The errors facing-service raises on purpose: catch ``FacingError`` for all of them."""

from .contract.errors import (
    ClientNotOpen,
    FacingError,
    NoService,
    QueryRefused,
    SettingsError,
    UnknownFrame,
)

__all__ = [
    "ClientNotOpen",
    "FacingError",
    "NoService",
    "QueryRefused",
    "SettingsError",
    "UnknownFrame",
]
