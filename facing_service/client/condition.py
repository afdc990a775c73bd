"""What the views say of the service's input: silent with its people held as they were
last heard, or a ROS 2 robot whose people cannot be read at all. Results alone cannot
tell it (a held person's last result looks current), so the service's status is asked,
once a second on a thread of its own, and a view's redraw never waits on the network."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Sequence

import zenoh

from ..contract.errors import FacingError
from ..contract.schemas import ServiceStatus
from .client import FacingClient
from .health import ask, broken_findings

#: How often the status is asked, and how long an answer is waited for.
PERIOD_S = 1.0
ASK_TIMEOUT_S = 0.8


def input_note(statuses: Sequence[ServiceStatus]) -> str | None:
    """One line on what the services' input gives now, or None when it is heard (each
    service in the namespace: the first one with something to say)."""
    for status in statuses:
        heard = status.input
        if heard is not None and heard.silent:
            people = "1 person" if heard.held == 1 else f"{heard.held} people"
            return (
                f"input silent for {heard.last_heard_s or 0.0:.1f} s: {people} held as last "
                "heard, not current (lost once each passes --hold-silent-s)"
            )
        if (broken := broken_findings(status)) and status.ros2 is not None:
            return f"no results from the robot: {broken[0]}: {status.ros2.findings[broken[0]]}"
    return None


class InputCondition:
    """The latest ``input_note`` of the client's services, asked every ``PERIOD_S`` once
    ``start``-ed; ``close`` stops and joins the thread (before the client's session
    closes: a thread still inside a query as the process ends aborts it). As a context,
    asked while the block runs."""

    def __init__(self, client: FacingClient) -> None:
        self.client = client
        self.note: str | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def refresh(self, statuses: Sequence[ServiceStatus] | None = None) -> None:
        """Ask now (or read ``statuses`` already asked) and keep what they say."""
        if statuses is None:
            statuses = []
            with contextlib.suppress(FacingError, zenoh.ZError, ValueError):
                statuses = ask(self.client.session, self.client.namespace, "*", ASK_TIMEOUT_S)
        self.note = input_note(statuses)

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="facing-input-condition")
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(PERIOD_S):
            self.refresh()

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(ASK_TIMEOUT_S + PERIOD_S)
            self._thread = None

    def __enter__(self) -> InputCondition:
        self.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()
