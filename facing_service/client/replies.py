"""What the services' answers to a client's query mean: the results, or the named error
that says why there are none (a typo in a frame, a refused parameter, no service at all).
Apart from the client's cache and callbacks: what a query's replies mean is one question."""

from __future__ import annotations

import time
from collections.abc import Iterable

import zenoh

from ..contract.errors import NoService, QueryRefused, UnknownFrame
from ..contract.schemas import EngagementState, FacingState, QueryError

#: What a service that knows the frame answers when nobody (asked for) is there.
_NOBODY = ("empty_frame", "not_tracked")


def facing_states(
    replies: Iterable[zenoh.Reply], selector: str, service_seen: bool, timeout_s: float
) -> list[FacingState]:
    """Every answering service's results. A frame is unknown only when no answer knew it
    (one service's refusal does not hide another's results), and a service that tracks
    nobody anywhere yet knows no frame, the right one no more than a typo: that is an
    empty answer, not ``UnknownFrame``. No answer at all, with no
    service seen alive (its liveliness token), is ``NoService``: with one alive, a
    wildcard frame that matches nobody gets no reply, and that is an empty answer."""
    states, unknown, answers = [], [], 0
    started = time.monotonic()
    for reply in replies:
        answers += 1
        if reply.ok is not None:
            states.append(FacingState.model_validate_json(reply.ok.payload.to_bytes()))
            continue
        assert reply.err is not None
        error = QueryError.model_validate_json(reply.err.payload.to_bytes())
        if error.error in _NOBODY:
            continue
        if error.error != "unknown_frame":
            raise QueryRefused(error.error, error.detail)
        refusal = UnknownFrame(error.error, error.detail)
        if refusal.nothing_tracked:  # an empty service reading any frame: nobody there yet
            continue  # (a robot app that starts before its tracker)
        unknown.append(refusal)
    if unknown and len(unknown) == answers:
        raise unknown[0]
    if not answers and not service_seen:
        raise NoService(
            f"no facing service answered {selector!r} {waited(started, timeout_s)}; none is "
            "seen alive: is one running, in this namespace, and does this client's endpoint "
            "reach it?"
        )
    return states


def waited(started: float, timeout_s: float) -> str:
    """How long a question that got no answer was waited for, since ``started``
    (``time.monotonic()``): zenoh ends one that nothing reachable can answer at once
    (NoService after 0.0 s said "within 2 s")."""
    took = time.monotonic() - started
    if took >= timeout_s / 2:
        return f"within {timeout_s:g} s"
    return f"(the question ended after {took:.1f} s: nothing reachable answers it)"


def engagement_states(replies: Iterable[zenoh.Reply]) -> list[EngagementState]:
    """Each body's engagement as the answering services hold it now."""
    return [
        EngagementState.model_validate_json(reply.ok.payload.to_bytes())
        for reply in replies
        if reply.ok is not None
    ]
