"""``facing-service run``: one service for the life of the process, responsive to SIGTERM and
Ctrl-C while zenoh opens (which may wait in native code for a router), and saying so
while its endpoints stay unreachable (zenoh retries them and says nothing).
"""

from __future__ import annotations

import logging
import os
import sys
import threading
import time

import zenoh

from ..config.disclosure import public_endpoint, zenoh_failure
from ..config.session import waiting_for_router
from ..config.settings import Settings
from .service import FacingService
from .threads import daemon_thread

log = logging.getLogger("facing_service")


def run_until(settings: Settings, stop: threading.Event) -> int:
    """``facing-service run``: the service until ``stop``; the process's exit code."""
    settings = waiting_for_router(settings)
    service = FacingService(settings)
    failure: list[zenoh.ZError] = []
    opened = threading.Event()

    def start() -> None:
        try:
            service.start()
        except zenoh.ZError as error:
            failure.append(error)
        finally:
            opened.set()

    # zenoh.open can wait indefinitely (a client with connect/timeout_ms:-1 waits for its
    # router) inside native code, where Python never runs signal handlers; so it runs on a
    # helper thread and this one stays responsive to SIGTERM and Ctrl-C.
    daemon_thread(start, "facing-open").start()
    if not wait_until_open(opened, settings, stop):  # nothing is open yet, nothing to close
        log.info("stopped before zenoh connected")
        logging.shutdown()
        os._exit(0)  # the helper thread is stuck in zenoh.open; do not wait for it
    if failure:
        print(zenoh_failure("run", failure[0]), file=sys.stderr)
        return 1
    try:
        stop.wait()  # the service's own threads work and say what happens to its links
    finally:
        service.close()
    log.info("stopped")
    return 0


#: How often ``run`` says that its connect endpoints are still unreachable.
UNREACHABLE_WARNING_S = 10.0


def wait_until_open(opened: threading.Event, settings: Settings, stop: threading.Event) -> bool:
    """True once zenoh.open has returned, False if ``stop`` came first. A client waiting
    for its router (``run``'s default in client mode, ``connect/timeout_ms: -1``) waits
    inside zenoh.open, where zenoh says nothing: this says it within a second, then every
    UNREACHABLE_WARNING_S, and says when the router answered."""
    start = time.monotonic()
    next_warning = start + min(1.0, UNREACHABLE_WARNING_S)
    warned = False
    while not opened.wait(0.1):
        if stop.is_set():
            return False
        if time.monotonic() >= next_warning:
            next_warning += UNREACHABLE_WARNING_S
            warned = True
            log.warning(
                "still waiting for a router at %s before the session opens (zenoh keeps "
                "trying; --exit-without-router exits instead); nothing is read or published "
                "meanwhile",
                ", ".join(public_endpoint(e) for e in settings.connect) or "any endpoint",
            )
    if warned:
        log.info("the router answered after %.1f s: the session is open", time.monotonic() - start)
    return True
