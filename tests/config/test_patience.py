"""A command waiting for its router says so, and stops waiting when asked to."""

from __future__ import annotations

import logging
import threading

import zenoh

from facing_service.config.patience import open_patiently, wait_until_open
from facing_service.config.settings import Settings


def test_waiting_for_the_router_is_said_within_a_second_and_a_stop_ends_it(caplog):
    stop, never = threading.Event(), threading.Event()
    threading.Timer(1.5, stop.set).start()
    with caplog.at_level(logging.WARNING, logger="facing_service"):
        assert wait_until_open(never, Settings(connect=["tcp/127.0.0.1:7999"]), stop) is False
    (said,) = [r.getMessage() for r in caplog.records]
    assert said.startswith("still waiting for a router at tcp/127.0.0.1:7999")


def test_what_opens_is_returned_and_zenohs_refusal_raised_on_the_callers_thread():
    stop = threading.Event()
    assert open_patiently(lambda: "session", Settings(), stop) == "session"

    def refused() -> str:
        raise zenoh.ZError("no such thing")

    try:
        open_patiently(refused, Settings(), stop)
    except zenoh.ZError as error:
        assert "no such thing" in str(error)
    else:
        raise AssertionError("zenoh's refusal was not raised")
