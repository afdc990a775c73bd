"""``facing-service router``: a zenoh router from what ``pip install`` already brings.

Deployments need a router (the secure example's ACL lives in one), and ``zenohd`` is a
separate binary that a robot or CI may not have. zenoh-python opens a session in router
mode with the same configuration file, access control included, so this is the same router
logic, not a stand-in.
"""

from __future__ import annotations

import json
import logging
import threading

import zenoh

from ..config.disclosure import public_endpoints
from ..config.session import mode_and_endpoints, zenoh_config
from ..config.settings import Settings

log = logging.getLogger("facing_service.router")


def router_config(settings: Settings) -> zenoh.Config:
    """The session config with the mode forced to router."""
    conf = zenoh_config(settings)
    conf.insert_json5("mode", '"router"')
    return conf


def serve(config: zenoh.Config, stop: threading.Event) -> None:
    """Run a router with ``config`` until ``stop`` is set."""
    _, listen = mode_and_endpoints(config, "listen")
    acl = json.loads(config.get_json("access_control/enabled"))
    with zenoh.open(config) as session:
        log.info(
            "zenoh router started: zenoh id %s, listening on %s, access control %s",
            session.zid(),
            public_endpoints(listen) or "nothing",
            "on" if acl else "off",
        )
        stop.wait()
    log.info("zenoh router stopped")
