"""Endpoints zenoh could never use are said before zenoh tries them (a peer would retry
forever in silence)."""

from __future__ import annotations

import pytest

from facing_service.config.endpoints import endpoint_problem


@pytest.mark.parametrize(
    "endpoint",
    ["tcp/127.0.0.1:7447", "tcp/[::1]:7447", "udp/robot.local:7447", "tls/router:7447",
     "unixsock-stream//tmp/zenoh.sock", "tcp/127.0.0.1:7447#iface=lo"],
)  # fmt: skip
def test_endpoints_zenoh_takes_pass(endpoint: str):
    assert endpoint_problem(endpoint) is None


@pytest.mark.parametrize(
    ("endpoint", "said"),
    [
        ("127.0.0.1:7447", "not <protocol>/<address> (tcp/127.0.0.1:7447?)"),
        ("http/robot:80", "protocol one of"),
        ("tcp/robot", "not <protocol>/<host>:<port>"),
        ("tcp/robot:seven", "not <protocol>/<host>:<port>"),
        ("tcp/robot:70000", "port 70000 out of range"),
        ("tcp/robot:0", "port 0 out of range"),
        ("tcp/[::1:7447", "an IPv6 address goes in [brackets]"),
        ("unixsock-stream/", "no address"),
    ],
)
def test_endpoints_zenoh_could_never_use_are_said(endpoint: str, said: str):
    problem = endpoint_problem(endpoint)
    assert problem is not None and said in problem


def test_a_listener_may_ask_for_any_free_port():
    assert endpoint_problem("tcp/127.0.0.1:0", listen=True) is None
