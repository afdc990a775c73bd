"""A silent input is held and said, not read as everyone leaving (issue 76).

An off-robot service hears the robot over a link that stalls (Wi-Fi roaming, a busy
channel: one to five seconds, then TCP delivers the backlog at once). Judged by when
poses arrive, every body went stale together at ``--stale-after-s`` and came back from
the backlog a moment later, ENGAGED people through ENGAGING. So the input as a whole is
watched: when nothing at all has come from it for ``after_s`` while people are tracked,
it is *silent*, and the tracker's time stands still (nobody goes stale, no level moves
with time alone) for up to ``hold_s``; when it speaks again, the tracker's time resumes
where it stopped (the silence is not counted against anyone: the backlog, or the next
poses, decide as they always do). A body that stops while the input goes on has left, as
before. Past ``hold_s`` the input is *gone*: time resumes whole, and everyone it held is
lost at once.

The input is what the service reads, as a whole: one robot's link, or the trackers that
publish its poses (two trackers into one service are silent only when both stop; one
alone stopping loses its people at ``--stale-after-s``, as before). Pure: the caller's
clock (seconds).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


@dataclass(frozen=True, slots=True)
class SilenceParams:
    after_s: float = 1.0  # nothing heard for this long, people tracked: silent
    hold_s: float = 10.0  # held at most this long after the last thing heard; 0: never


class Change(Enum):
    """What the input's silence did, to be said."""

    SILENT = "silent"  # nothing heard for after_s: the people are held
    BACK = "back"  # heard again while held: time resumes where it stopped
    GONE = "gone"  # nothing heard for hold_s: the people held are lost


class InputSilence:
    """The input's last sign of life, and whether its people are held now."""

    def __init__(self, params: SilenceParams) -> None:
        self.params = params
        self.last_heard: float | None = None
        self.holding = False  # silent, and its people held
        self.silences = 0  # how many times it went silent
        self.longest_s = 0.0  # the longest silence that ended (back or gone)

    def heard(self, now: float) -> float | None:
        """Something came from the input at ``now``: how long the silence it ends held
        the tracker's time (to be added to it), None when nothing was held."""
        held = None
        if self.holding and self.last_heard is not None:
            held = max(now - self.last_heard, 0.0)
            self.longest_s = max(self.longest_s, held)
            self.holding = False
        self.last_heard = now
        return held

    def next_due(self, tracking: bool) -> float | None:
        """When ``look`` has something to say (the caller's clock), if ever."""
        if self.last_heard is None or self.params.hold_s <= 0:
            return None
        if self.holding:
            return self.last_heard + self.params.hold_s
        return self.last_heard + self.params.after_s if tracking else None

    def look(self, now: float, tracking: bool) -> Change | None:
        """Whether the input just went silent (``tracking``: people are held now) or its
        silence just outlasted the bound (time resumes whole: they go stale)."""
        due = self.next_due(tracking)
        if due is None or now < due or self.last_heard is None:
            return None
        if self.holding:
            self.holding = False
            self.longest_s = max(self.longest_s, now - self.last_heard)
            return Change.GONE
        if now - self.last_heard >= self.params.hold_s:
            return None  # (first looked at past the bound: as without a hold)
        self.holding = True
        self.silences += 1
        return Change.SILENT
