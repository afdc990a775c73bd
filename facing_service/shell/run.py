"""``facing-service run``: one service for the life of the process, responsive to SIGTERM and
Ctrl-C while zenoh opens (``config.patience``: it may wait in native code for a router).
"""

from __future__ import annotations

import logging
import sys
import threading

import zenoh

from ..config.disclosure import zenoh_failure
from ..config.patience import open_patiently
from ..config.session import waiting_for_router
from ..config.settings import Settings
from .service import FacingService

log = logging.getLogger("facing_service")


def run_until(settings: Settings, stop: threading.Event) -> int:
    """``facing-service run``: the service until ``stop``; the process's exit code."""
    settings = waiting_for_router(settings)
    service = FacingService(settings)
    try:
        started = open_patiently(service.start, settings, stop)
    except zenoh.ZError as error:
        print(zenoh_failure("run", error), file=sys.stderr)
        return 1
    if started is None:  # nothing is open yet, nothing to close; the helper thread stuck
        log.info("stopped before zenoh connected")  # in zenoh.open ends with the process
        return 0  # (cli.entry ends it without waiting)
    try:
        stop.wait()  # the service's own threads work and say what happens to its links
    finally:
        service.close()
    log.info("stopped")
    return 0
