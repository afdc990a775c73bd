"""The errors facing-service raises on purpose, under one base class: an application
catches ``FacingError`` for all of them, or one by name (``facing_service.errors``)."""

from __future__ import annotations

from collections.abc import Iterable


class FacingError(Exception):
    """Every error facing-service raises on purpose."""


class SettingsError(FacingError, ValueError):
    """A bad setting, as one line that names the flag or variable it came from and never
    quotes a secret (see ``config.disclosure``)."""


class QueryRefused(FacingError, ValueError):
    """The service refused a query: ``reason`` is the reply's ``error`` (``bad_parameter``,
    ``unknown_frame``), ``detail`` its explanation."""

    def __init__(self, reason: str, detail: str) -> None:
        super().__init__(f"{reason}: {detail}")
        self.reason = reason
        self.detail = detail


class UnknownFrame(QueryRefused):
    """A query named a frame the service does not know (the detail names those it tracks):
    a typo in a frame name, not an empty room."""

    @property
    def nothing_tracked(self) -> bool:
        """The service tracks nobody in any frame (empty, as it starts): every frame is
        unknown to it, a misspelt one no more than the right one."""
        return self.detail.endswith(_TRACKED + _NONE)


_TRACKED, _NONE = "frames tracked: ", "none"


def unknown_frame_detail(frame: str, tracked: Iterable[str]) -> str:
    """The ``unknown_frame`` reply's detail, naming the frames the service tracks (what
    ``UnknownFrame.nothing_tracked`` reads back)."""
    return f"no frame {frame!r} in this service; {_TRACKED}{', '.join(sorted(tracked)) or _NONE}"


class NoService(FacingError, ConnectionError):
    """No facing service answered a query: none is running, or the client's endpoint,
    namespace or access rights do not reach it (an empty service answers, with nobody)."""


class ClientNotOpen(FacingError, RuntimeError):
    """A client was used before ``open()`` or after ``close()``."""
