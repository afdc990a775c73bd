from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
import zenoh

from facing_service.config.settings import Settings
from facing_service.shell.service import FacingService

from loopback import (
    LOOPBACK_CFG,
    Recorder,
    endpoint,
    free_port,
    loopback_config,
    wait_until_answered,
)
from oracles import in_ci, shared_data_missing
from routers import Router


def pytest_configure(config: pytest.Config) -> None:
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
    if in_ci():
        pytest.fail(f"{missing}; CI runs every test, so it must be there")
    pytest.skip(missing)


class Network:
    """Starts services and client sessions on loopback and closes all of them afterwards."""

    def __init__(self) -> None:
        self._closers: list[Any] = []

    def service(self, **settings: Any) -> tuple[FacingService, str]:
        ep = endpoint(free_port())
        params = {
            "listen": [ep],
            "no_multicast_scouting": True,
            "cfg": LOOPBACK_CFG,
            "base_frame": "cam",
        } | settings
        service = FacingService(Settings(**params)).start()
        self._closers.append(service.close)
        return service, ep

    def robot_service(self, router: str, **settings: Any) -> FacingService:
        """A service reading a ROS 2 robot's topics (``--input ros2``) through the router
        at ``router``, in client mode, as it runs beside a robot."""
        params = {"mode": "client", "connect": [router], "listen": [], "input": "ros2"}
        service, _ = self.service(**(params | settings))
        return service

    def client(self, connect: str, mode: str = "peer", timestamping: bool = False) -> zenoh.Session:
        """A session connecting to ``connect``; ``timestamping``: stamping what it puts
        (as zenohd, which runs zenoh-bridge-ros2dds, does)."""
        conf = loopback_config(connect=[connect], mode=mode)
        if timestamping:
            conf.insert_json5("timestamping/enabled", "true")
        session = zenoh.open(conf)
        self._closers.append(session.close)
        return session

    def router(self, config_json5: str | None = None, port: int | None = None) -> Router:
        """A router process: plain on a free loopback port, or as ``config_json5`` says
        (which then listens on ``port``)."""
        if config_json5 is None:
            port = free_port()
            config_json5 = str(loopback_config(listen=[endpoint(port)], mode="router"))
        assert port is not None
        router = Router(config_json5, port).start()
        self._closers.append(router.stop)
        return router

    def recorder(self, session: zenoh.Session, key_expr: str) -> Recorder:
        recorder = Recorder(session, key_expr)
        self._closers.append(recorder.close)
        return recorder

    def close(self) -> None:
        for close in reversed(self._closers):
            close()
        self._closers.clear()


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
        return service, client, recorder

    return make
