"""The consumer's side: ``FacingClient`` (who faces the robot, by callbacks, without a
topic in sight; ``AsyncFacingClient`` for asyncio), ``watch`` (a live table), ``sim`` (a
tracker to test against) and ``health`` (is a service answering, and why not)."""

from .aio import AsyncFacingClient
from .client import FacingClient
from .options import ClientOptions

__all__ = ["AsyncFacingClient", "ClientOptions", "FacingClient"]
