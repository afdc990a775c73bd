from __future__ import annotations

import signal
from collections.abc import Iterator
from typing import Any

import pytest

from loopback import wait_until_answered
from network import Network, wait_until_heard
from oracles import shared_data_missing, shared_data_required


def pytest_configure(config: pytest.Config) -> None:
    # Started in the background of a non-interactive shell (a CI script's `&`, nohup),
    # this process inherits SIGINT ignored, and so would every command a test starts: a
    # Ctrl-C a test sends before the command sets its own handler would be lost, and the
    # command never end (seen once in CI). Tests send signals as a terminal would.
    if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    config.addinivalue_line(
        "markers",
        "shared_data: reads ../shared/data (skipped where it is absent, failed in CI)",
    )


def pytest_runtest_setup(item: pytest.Item) -> None:
    """A test of the shared data, on a machine without it: skipped with the reason on a
    user's clone, failed in CI (which must run every test). Before its fixtures, some of
    which read the data."""
    if item.get_closest_marker("shared_data") is None:
        return
    missing = shared_data_missing()
    if missing is None:
        return
    if shared_data_required():
        pytest.fail(f"{missing}; CI runs every test, so it must be there")
    pytest.skip(missing)


@pytest.fixture
def net() -> Iterator[Network]:
    network = Network()
    try:
        yield network
    finally:
        network.close()


@pytest.fixture
def rig(net: Network):
    """The shell's end-to-end tests: a service on 'cam' (``**settings`` over the
    defaults) plus a connected client recording every result under hri/."""

    def make(**settings: Any):
        service, ep = net.service(**settings)
        client = net.client(ep)
        recorder = net.recorder(client, "hri/**/facing/**")
        wait_until_answered(client, "hri/facing/cam")
        wait_until_heard(service)  # the recorder's: every result is then sent
        return service, client, recorder

    return make
