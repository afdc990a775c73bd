"""When a person whose poses stopped is lost: the input's silence, and each person's own.

An off-robot service hears the robot over a link that stalls (Wi-Fi roaming, a busy
channel: one to five seconds, then TCP delivers the backlog at once). Judged by when
poses arrive, every person would go stale together and come back from the backlog a
moment later. So the input as a whole is watched too, and one rule decides who is lost:

- A person is lost once its own poses have stopped for ``stale_s`` while the input is
  *heard*: something of it came within the last ``after_s`` and it is not just back from
  a silence (``settle_s``: the rest of a backlog, carrying this person's poses, is still
  arriving). Whatever the rate of the others: one pose of anyone, every 3 s, is enough
  to tell that a person who stopped has left.
- While the input is *silent* (nothing of it for ``after_s``, people tracked), its
  people are held: a person is lost only once its own poses have stopped for
  ``max(stale_s, hold_s)``, however many silences there were (no time is shifted or
  carried from one silence to the next: each person's bound is from its own last pose).
- Only what the input says whole is heard: a refused sample (junk, an invalid key) is
  not the input speaking.

So the staleness in force at any moment (``staleness_s``) is ``stale_s`` or
``max(stale_s, hold_s)``, and the tracker loses every body older than it.

A tracker slower than ``after_s`` (a 1 Hz detector) makes each pause between its
messages a silence: it holds its people as it should (nobody is lost between poses), but
it is the input's rate, not a stall. The input's period is learned from the gaps between
what is heard: a silence is worth logging only once it lasts twice that period (and
``after_s``), and a period no shorter than ``after_s`` is logged once (``Change.SLOW``).

Invariants: the staleness in force is never below ``stale_s`` nor above
``max(stale_s, hold_s)``; nothing here moves a person's own time. Pure: the caller's
clock (seconds).
"""

from __future__ import annotations

import statistics
from collections import deque
from dataclasses import dataclass
from enum import Enum

#: After a silence, how long what arrives is read as the rest of a backlog before anyone
#: missing from it is judged: TCP delivers a stalled link's backlog within milliseconds.
SETTLE_S = 0.25
#: Gaps between what is heard that the input's period is learned from (their median),
#: and how many are needed before it is trusted.
PERIOD_GAPS = 9
PERIOD_KNOWN_AFTER = 3


@dataclass(frozen=True, slots=True)
class SilenceParams:
    after_s: float = 1.0  # nothing heard for this long, people tracked: silent
    hold_s: float = 10.0  # people held at most this long after their own last pose; 0: never
    stale_s: float = 2.0  # a person not heard for this long, the input heard, is lost
    settle_s: float = SETTLE_S


class Change(Enum):
    """What the input's silence did that is worth logging."""

    SILENT = "silent"  # nothing heard for longer than its rate explains: people are held
    BACK = "back"  # heard again after a silence that was logged
    SLOW = "slow"  # the input's own period is no shorter than after_s (logged once)


class InputSilence:
    """The input's last sign of life, whether its people are held now, and its period."""

    def __init__(self, params: SilenceParams) -> None:
        self.params = params
        self.last_heard: float | None = None
        self.holding = False  # silent now: its people are held
        self.silences = 0  # silences logged (longer than the input's rate explains)
        self.longest_s = 0.0  # the longest silence logged, once it ended
        self.ended_s = 0.0  # how long the last silence that ended lasted
        self._back_at: float | None = None  # heard again after a silence: when
        self._logged = False  # the current silence was logged (so is its end)
        self._logged_slow = False
        self._losses_logged = False  # people lost to the hold were logged in this silence
        self._gaps: deque[float] = deque(maxlen=PERIOD_GAPS)

    @property
    def stalled(self) -> bool:
        """Silent for longer than the input's own rate explains: a stall, logged (what the
        status shows as silent; a slow tracker's pauses hold its people, unlogged)."""
        return self.holding and self._logged

    @property
    def period_s(self) -> float | None:
        """The input's usual gap between what is heard, once known."""
        if len(self._gaps) < PERIOD_KNOWN_AFTER:
            return None
        return statistics.median(self._gaps)

    def heard(self, now: float) -> Change | None:
        """Something whole came from the input at ``now``: BACK when it ends a silence
        that was logged."""
        change = None
        if self.last_heard is not None:
            gap = max(now - self.last_heard, 0.0)
            self._gaps.append(gap)
            if gap >= self.params.after_s:  # (held or not yet looked at: a silence ended)
                self._back_at, self.ended_s = now, gap
                if self.holding and self._logged:
                    self.longest_s = max(self.longest_s, gap)
                    change = Change.BACK
        self.holding = self._logged = self._losses_logged = False
        self.last_heard = now
        return change

    def staleness_s(self, now: float) -> float:
        """How long a person's poses must have stopped, at ``now``, for it to be lost."""
        p = self.params
        settling = self._back_at is not None and now < self._back_at + p.settle_s
        if p.hold_s > 0 and (settling or self._silent(now)):
            return max(p.stale_s, p.hold_s)
        return p.stale_s

    def first_losses(self) -> bool:
        """People were just lost to the hold: True the first time in a silence (the rest
        of its people, each at its own bound, follow without a line of their own)."""
        first, self._losses_logged = not self._losses_logged, True
        return first

    def _silent(self, now: float) -> bool:
        return self.last_heard is not None and now - self.last_heard >= self.params.after_s

    def next_due(self, tracking: bool) -> float | None:
        """When ``look`` or ``staleness_s`` next changes (the caller's clock), if ever."""
        if self.last_heard is None or self.params.hold_s <= 0:
            return None
        due = []
        if self._back_at is not None:
            due.append(self._back_at + self.params.settle_s)
        if tracking and not self.holding:
            due.append(self.last_heard + self.params.after_s)
        if tracking and self.holding and not self._logged:
            due.append(self.last_heard + self._worth_logging_s())
        return min(due, default=None)

    def _worth_logging_s(self) -> float:
        """How long a silence lasts before it is more than the input's own rate."""
        period = self.period_s
        rate = 2 * (period if period is not None else self.params.after_s)
        return max(self.params.after_s, rate)

    def look(self, now: float, tracking: bool) -> Change | None:
        """Whether the input just went silent (``tracking``: people are held now), and
        whether that is worth logging."""
        if self._back_at is not None and now >= self._back_at + self.params.settle_s:
            self._back_at = None
        if self.last_heard is None or self.params.hold_s <= 0 or not tracking:
            return None
        silent = self.holding = self._silent(now)
        period = self.period_s
        if period is not None and period >= self.params.after_s and not self._logged_slow:
            self._logged_slow = True
            return Change.SLOW
        if not silent:
            return None
        if not self._logged and now - self.last_heard >= self._worth_logging_s():
            self._logged = True
            self.silences += 1
            return Change.SILENT
        return None
