"""A publishing command says while it runs that no facing service hears it
(``simulate`` and ``camera`` said so only at their end, and a webcam has no end)."""

from __future__ import annotations

import threading
import time

import zenoh

from facing_service.client.presence import ServiceWatch
from facing_service.testing import LOOPBACK_FLAGS, loopback_config, running_cli

from loopback import endpoint, free_port


class Said:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self.event = threading.Event()

    def __call__(self, line: str) -> None:
        self.lines.append(line)
        self.event.set()


def test_simulate_to_nowhere_says_so_while_it_runs():
    """Before: lines of poses published for the whole run, the warning only at its end."""
    nowhere = endpoint(free_port())
    args = ("simulate", "-e", nowhere, *LOOPBACK_FLAGS, "--duration-s", "20")
    with running_cli(*args) as proc:
        assert proc.stdout is not None
        started = time.monotonic()
        lines = []
        while not any("nobody hears yet" in line for line in lines):
            lines.append(proc.stdout.readline())
            assert lines[-1], lines
        said_after = time.monotonic() - started
        assert proc.poll() is None  # said while running, not at the end
    (warning,) = [line for line in lines if "nobody hears yet" in line]
    assert f"nothing answers at {nowhere}" in warning
    assert said_after < 10, said_after


def test_a_wrong_namespace_is_said_with_those_that_have_a_service(net):
    _, ep = net.service()
    said = Said()
    session = net.client(ep)
    with ServiceWatch(session, "camera", "robot1/hri", [ep], said, grace_s=0.5):
        assert said.event.wait(10)
    (line,) = said.lines
    assert line.startswith("facing-service camera: no facing service in namespace 'robot1/hri'")
    assert "(namespaces with one: hri)" in line


def test_nothing_is_said_when_a_service_hears_and_its_arrival_is_said(net):
    _, ep = net.service()
    said = Said()
    with ServiceWatch(net.client(ep), "simulate", "hri", [ep], said, grace_s=0.3):
        time.sleep(1.5)
    assert said.lines == []
    port = free_port()
    said = Said()
    with (
        zenoh.open(loopback_config(listen=[endpoint(port)])) as session,
        ServiceWatch(session, "simulate", "hri", [], said, grace_s=0.3),
    ):
        assert said.event.wait(10)
        said.event.clear()
        net.service(connect=[endpoint(port)])
        assert said.event.wait(10)
    assert [line.split(": ", 1)[1][:19] for line in said.lines] == [
        "nothing answers: no",
        "a facing service he",
    ]
