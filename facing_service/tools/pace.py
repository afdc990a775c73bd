"""A recording played at its recorded pace: each message due at its recorded time since
the first, divided by the rate (``replay`` of a ROS 2 bag and of a session alike)."""

from __future__ import annotations

import time


class RecordedPace:
    """``wait(at_ns)`` sleeps until a message recorded at ``at_ns`` is due; the first
    message's time is where the recording starts unless ``first_ns`` says otherwise (a
    bag's own start)."""

    def __init__(self, rate: float, first_ns: int | None = None) -> None:
        self.rate = rate
        self.first_ns = first_ns
        self.started = time.monotonic()

    def wait(self, at_ns: int) -> None:
        if self.first_ns is None:
            self.first_ns = at_ns
        due = self.started + (at_ns - self.first_ns) / 1e9 / self.rate
        if (wait := due - time.monotonic()) > 0:
            time.sleep(wait)

    def recorded_s(self, at_ns: int) -> float:
        """How far into the recording ``at_ns`` is."""
        return 0.0 if self.first_ns is None else (at_ns - self.first_ns) / 1e9

    def elapsed_s(self) -> float:
        return time.monotonic() - self.started
