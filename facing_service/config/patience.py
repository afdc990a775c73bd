"""Opening a session that may wait for its router: ``run``, ``watch`` and ``view`` start in
any order beside a robot's router. zenoh.open can then wait indefinitely in native code
(a client with ``connect/timeout_ms: -1``), where Python never runs signal handlers and
zenoh says nothing; so the opening runs on a helper thread, the caller's thread stays
responsive to SIGTERM and Ctrl-C, and the wait is said within a second and then
periodically.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, TypeVar

import zenoh

from .disclosure import public_endpoints

if TYPE_CHECKING:
    from .settings import Settings

log = logging.getLogger("facing_service")

T = TypeVar("T")

#: How often a waiting command says that its connect endpoints are still unreachable.
UNREACHABLE_WARNING_S = 10.0


def open_patiently(open_: Callable[[], T], settings: Settings, stop: threading.Event) -> T | None:
    """What ``open_`` returns once zenoh has opened, or None if ``stop`` came first (the
    helper thread is then still inside zenoh.open: the process ends without waiting for
    it, ``cli.entry``). zenoh's own refusal is raised here, on the caller's thread."""
    return _in_background(open_, lambda opened: wait_until_open(opened, settings, stop))


def open_interruptibly(open_: Callable[[], T]) -> T:
    """What ``open_`` returns once zenoh has opened, for a command that waits no longer
    than its own timeout and says nothing meanwhile (``health``): Ctrl-C raises
    KeyboardInterrupt on the caller's thread within 0.1 s, where zenoh.open held it in
    native code for the whole connect timeout (15.6 s)."""

    def until_opened(opened: threading.Event) -> bool:
        while not opened.wait(0.1):  # a KeyboardInterrupt comes between two waits
            pass
        return True

    opened = _in_background(open_, until_opened)
    assert opened is not None  # until_opened never gives up
    return opened


def _in_background(open_: Callable[[], T], wait: Callable[[threading.Event], bool]) -> T | None:
    """``open_()`` on a helper thread while ``wait(opened)`` waits on the caller's (False:
    it gave up, None returned)."""
    opened = threading.Event()
    result: list[T] = []
    failure: list[zenoh.ZError] = []

    def attempt() -> None:
        try:
            result.append(open_())
        except zenoh.ZError as error:
            failure.append(error)
        finally:
            opened.set()

    threading.Thread(target=attempt, name="facing-open", daemon=True).start()
    if not wait(opened):
        return None
    if failure:
        raise failure[0]
    return result[0]


def wait_until_open(opened: threading.Event, settings: Settings, stop: threading.Event) -> bool:
    """True once zenoh.open has returned, False if ``stop`` came first. A client waiting
    for its router waits inside zenoh.open, where zenoh says nothing: this says it within a
    second, then every UNREACHABLE_WARNING_S, and says when the router answered."""
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
                public_endpoints(settings.connect) or "any endpoint",
            )
    if warned:
        log.info("the router answered after %.1f s: the session is open", time.monotonic() - start)
    return True
