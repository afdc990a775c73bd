"""``facing-service health``: is a service answering, as a container's health check asks.

A session just opened has not discovered anybody yet, a peer especially: a query sent at
once reaches nobody, and a running service would be reported absent (seen in 5 of 20
tries). So the check first waits, up to its time-out, for a matching service's liveliness
token, then asks for the status until an answer or the time-out.
"""

from __future__ import annotations

import time

import zenoh

from . import keys
from .schemas import ServiceStatus


def statuses(
    session: zenoh.Session, namespace: str, instance: str, timeout: float
) -> list[ServiceStatus]:
    """The status of every service matching ``instance`` (``*``: any) that answers within
    ``timeout`` seconds; empty when none does."""
    deadline = time.monotonic() + timeout
    token = keys.service_token(namespace, instance)
    while (left := deadline - time.monotonic()) > 0:
        replies = session.liveliness().get(token, timeout=min(0.25, left))
        if any(reply.ok is not None for reply in replies):
            answers = ask(session, namespace, instance, max(deadline - time.monotonic(), 0.1))
            if answers:
                return answers
        time.sleep(min(0.05, max(deadline - time.monotonic(), 0)))
    return []


def ask(
    session: zenoh.Session, namespace: str, instance: str, timeout: float
) -> list[ServiceStatus]:
    """One status query: the answers that came within ``timeout``."""
    return [
        ServiceStatus.model_validate_json(reply.ok.payload.to_bytes())
        for reply in session.get(keys.status_key(namespace, instance), timeout=timeout)
        if reply.ok is not None
    ]
