"""``facing-service run``'s loop: the service until asked to stop, an exit code for each
way it ends (zenoh refusing the session, stopped before zenoh connected, stopped)."""

from __future__ import annotations

import threading

from facing_service.config.settings import Settings
from facing_service.shell.run import run_until

from loopback import endpoint, free_port, get, wait_until


def test_it_serves_until_stopped_and_exits_0(net):
    ep = endpoint(free_port())
    settings = Settings(listen=[ep], no_multicast_scouting=True, instance="runner")
    stop = threading.Event()
    codes: list[int] = []
    thread = threading.Thread(target=lambda: codes.append(run_until(settings, stop)))
    thread.start()
    try:
        client = net.client(ep)
        wait_until(lambda: get(client, "hri/services/facing/runner/status", 0.5), 10, "status")
    finally:
        stop.set()
        thread.join(10)
    assert codes == [0]


def test_a_session_zenoh_refuses_exits_1_with_one_line(capsys):
    settings = Settings(listen=["tcp/192.0.2.1:1"], no_multicast_scouting=True)  # not ours
    assert run_until(settings, threading.Event()) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("facing-service run:")


def test_stopped_before_zenoh_connected_exits_0():
    stop = threading.Event()
    stop.set()  # a router that never comes: the client waits, and is stopped meanwhile
    settings = Settings(mode="client", connect=[endpoint(free_port())])
    assert run_until(settings, stop) == 0
