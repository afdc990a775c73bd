"""Whether the service's session has anybody to talk to, said when it changes.

Zenoh reconnects by itself and says nothing: a router restarting (rmw_zenohd, the bridge)
or a wifi drop left no trace in the log and an unchanged status. The watch polls the
session's routers and peers (a cheap native call) a few times a second from its own
thread, logs the loss and the return with how long it lasted, reminds while it lasts, and
gives the status the outage's length.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

from ..config.disclosure import public_endpoints

log = logging.getLogger("facing_service")

#: How often the session's links are read.
PERIOD_S = 0.2
#: A session that never had a link is said to have none after this (a router up at start
#: answers well within it), and reminded of every ``REMINDER_S`` while it lasts.
FIRST_SAY_S = 1.0
REMINDER_S = 10.0
#: An outage longer than this makes the status "no router" (health fails); shorter ones
#: (a router restarting) are shown in ``outage_s`` alone.
NO_ROUTER_AFTER_S = 5.0


class LinkWatch:
    """Reads ``links()`` (routers and peers, zenoh ids) until ``closing``; only its thread
    writes its state, the status reads it."""

    def __init__(
        self,
        links: Callable[[], dict[str, list[str]]],
        endpoints: list[str],
        clock: Callable[[], float],
        closing: threading.Event,
    ) -> None:
        self._links = links
        self._where = public_endpoints(endpoints)
        self._clock = clock
        self._closing = closing
        self._since: float | None = None  # nobody to talk to since then

    def outage_s(self) -> float | None:
        """How long the session has had nobody to talk to, or None while it has somebody
        (or, without connect endpoints, while it waits to be found)."""
        since = self._since
        return None if since is None else self._clock() - since

    def run(self) -> None:
        """Until ``closing``. Only a session told where to connect can be said to have
        lost its way: one that only listens waits to be found, and says nothing."""
        if not self._where:
            self._closing.wait()  # alive like the service's other threads, with nothing to say
            return
        start = self._clock()
        had = False  # ever had a link
        next_say = start + FIRST_SAY_S
        while True:  # the first look at once, then every PERIOD_S
            now = self._clock()
            links = self._links()
            if links["routers"] or links["peers"]:
                if self._since is not None:
                    log.warning(
                        "%s %s after %.1f s: results flow again",
                        "back in touch with" if had else "reached",
                        self._where,
                        now - self._since,
                    )
                self._since, had = None, True
            elif had and self._since is None:  # just lost
                self._since, next_say = now, now + REMINDER_S
                log.warning(
                    "lost every router and peer at %s (zenoh reconnects, --reconnect-s); "
                    "results reach nobody meanwhile",
                    self._where,
                )
            elif not had and now >= next_say:  # never had one
                self._since = self._since if self._since is not None else start
                next_say = now + REMINDER_S
                log.warning(
                    "no router or peer reachable at %s yet (zenoh keeps trying); results "
                    "reach nobody meanwhile",
                    self._where,
                )
            elif self._since is not None and now >= next_say:  # (lost: _since is set)
                next_say = now + REMINDER_S
                log.warning(
                    "still no router or peer at %s after %.0f s (zenoh keeps trying)",
                    self._where,
                    now - self._since,
                )
            if self._closing.wait(PERIOD_S):
                return
