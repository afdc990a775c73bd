"""Real zenoh sessions, services and routers on loopback, every one closed afterwards: the
``net`` fixture's (conftest.py), and a module fixture's that needs one for longer."""

from __future__ import annotations

from typing import Any

import zenoh

from facing_service.config.settings import Settings
from facing_service.shell.service import FacingService

from loopback import LOOPBACK_CFG, Recorder, endpoint, free_port, loopback_config, wait_until
from routers import Router


def wait_until_heard(service: FacingService, heard: bool = True, timeout: float = 10.0) -> None:
    """Until the service's status says a subscriber matches its result keys (``heard``), or
    that none does: zenoh tells it a moment after the subscriber exists, and results are
    not sent before (docs/contract.md). A test that counts every result waits for it."""
    wait_until(lambda: service.status().results_heard is heard, timeout, f"results_heard {heard}")


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
