"""The link watch: said when the session loses everybody and when it is back, with the
outage's length in the status (fed its links and clock, no network)."""

from __future__ import annotations

import logging
import threading

from facing_service.shell import links as links_module
from facing_service.shell.links import LinkWatch


class Steps:
    """A clock and a links() that advance one PERIOD_S per read, along a script of
    whether anybody is reachable; the watch's closing event is set at the script's end."""

    def __init__(self, reachable: list[bool], closing: threading.Event) -> None:
        self.reachable, self.closing, self.t, self.i = reachable, closing, 0.0, 0
        self.outages: list[float | None] = []

    def clock(self) -> float:
        return self.t

    def links(self) -> dict[str, list[str]]:
        up = self.reachable[min(self.i, len(self.reachable) - 1)]
        self.i += 1
        self.t += links_module.PERIOD_S
        if self.i >= len(self.reachable):
            self.closing.set()
        return {"routers": ["r"] if up else [], "peers": []}


def run(reachable: list[bool], endpoints=("tcp/10.0.0.1:7447",)) -> tuple[Steps, LinkWatch]:
    closing = threading.Event()
    steps = Steps(reachable, closing)
    watch = LinkWatch(steps.links, list(endpoints), steps.clock, closing)
    watch.run()
    return steps, watch


def test_a_loss_and_a_return_are_each_said_once_with_how_long(caplog):
    caplog.set_level(logging.WARNING, logger="facing_service")
    run([True, True, False, False, False, True, True])
    said = [r.getMessage() for r in caplog.records]
    assert len(said) == 2, said
    assert said[0].startswith("lost every router and peer at tcp/10.0.0.1:7447")
    assert said[1].startswith("back in touch with tcp/10.0.0.1:7447 after 0.")


def test_the_outage_lasts_until_a_link_returns():
    _, watch = run([True, False, False])
    assert watch.outage_s() is not None and watch.outage_s() > 0
    _, healthy = run([False, True])
    assert healthy.outage_s() is None


def test_a_session_that_only_listens_says_nothing(caplog):
    closing = threading.Event()
    closing.set()
    watch = LinkWatch(lambda: {"routers": [], "peers": []}, [], lambda: 0.0, closing)
    watch.run()
    assert watch.outage_s() is None and not caplog.records
