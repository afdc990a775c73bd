"""Whether a facing service is there to hear a publishing command, said while it runs.

``simulate`` and ``camera`` publish as a tracker would; with a wrong endpoint or namespace
they said so only at their end, and a webcam has no end. ``run`` warns within
a second and ``health`` within its time-out: these say it after a short grace, once, with
what to try, and say again once a service appears.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from types import TracebackType

import zenoh

from .health import instances_seen, no_service_seen

#: How long a session may take to find a service before its absence is said.
GRACE_S = 2.0


class ServiceWatch:
    """A daemon thread that looks for a facing service's liveliness token in
    ``namespace``: absent after ``grace_s``, ``say`` why in one line (and what to try);
    present later, ``say`` so. Nothing is said when a service is there from the start."""

    def __init__(
        self,
        session: zenoh.Session,
        command: str,
        namespace: str,
        connect: Sequence[str],
        say: Callable[[str], None],
        grace_s: float = GRACE_S,
    ) -> None:
        self._session, self._command, self._namespace = session, command, namespace
        self._connect, self._say, self._grace_s = list(connect), say, grace_s
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._watch, name="facing-watch", daemon=True)

    def __enter__(self) -> ServiceWatch:
        self._thread.start()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self._stop.set()
        self._thread.join(timeout=2.0)

    def _watch(self) -> None:
        try:
            self._say_absence()
        except zenoh.ZError:  # the session closing under the watch: nothing left to say
            return

    def _say_absence(self) -> None:
        if self._stop.wait(self._grace_s) or self._seen():
            return
        why = no_service_seen(self._session, self._namespace, self._connect)
        self._say(
            f"facing-service {self._command}: {why}; publishing on, but nobody hears yet "
            "(try: facing-service health with the same -m/-e/--namespace)"
        )
        while not self._stop.wait(1.0):
            if self._seen():
                self._say(f"facing-service {self._command}: a facing service hears it now")
                return

    def _seen(self) -> bool:
        return bool(instances_seen(self._session, self._namespace))
