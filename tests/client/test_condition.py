"""What the views say of the service's input (client/condition): silent with its people
held, or a robot whose people cannot be read; seen as people see it, in the terminal
(``watch --once``) and on the page (Debian's chromium)."""

from __future__ import annotations

import threading
import time

import pytest

from facing_service.client.client import FacingClient
from facing_service.client.condition import input_note
from facing_service.client.view.live import run_view
from facing_service.contract.schemas import InputHealth, Ros2Status, ServiceStatus
from facing_service.testing import LOOPBACK_FLAGS, free_port, running_cli

from browser import Browser
from loopback import loopback_config, send
from poses import pose_json


def status(**fields) -> ServiceStatus:
    return ServiceStatus.model_construct(**({"input": None, "ros2": None} | fields))


def heard(silent: bool, held: int = 0, last_heard_s: float = 0.1) -> InputHealth:
    return InputHealth(last_heard_s=last_heard_s, silent=silent, held=held, silences=0,
                       longest_silence_s=0.0)  # fmt: skip


def test_a_silent_input_is_said_with_the_people_it_holds():
    said = input_note([status(input=heard(True, held=3, last_heard_s=4.25))])
    assert said == (
        "input silent for 4.2 s: 3 people held as last heard, not current (lost once each "
        "passes --hold-silent-s)"
    )
    assert "1 person held" in input_note([status(input=heard(True, held=1))])


def test_a_robot_whose_people_cannot_be_read_is_said_and_a_heard_input_is_not():
    ros2 = Ros2Status.model_construct(
        findings={"base_frame_not_in_tree": "base_link is not in the TF tree", "other": "x"}
    )
    assert input_note([status(input=heard(False), ros2=ros2)]) == (
        "no results from the robot: base_frame_not_in_tree: base_link is not in the TF tree"
    )
    assert input_note([status(input=heard(False))]) is None
    assert input_note([]) is None


def stream(tracker, seconds: float, start_s: float) -> float:
    """A person facing the robot 2 m ahead, at 30 Hz for ``seconds``: the next start."""
    for i in range(round(seconds * 30)):
        at = start_s + i / 30
        sec, nanosec = divmod(round(at * 1e9), 1_000_000_000)
        send(tracker, "hri/bodies/ann/pose/cam",
             pose_json("ann", "cam", x=2.0, y=0.0, sec=sec, nanosec=nanosec))  # fmt: skip
        time.sleep(1 / 30)
    return start_s + seconds


@pytest.mark.slow
def test_watch_once_says_the_input_is_silent_and_its_people_held(net):
    service, ep = net.service(silent_after_s=0.5, hold_silent_s=30.0)
    tracker = net.client(ep)
    time.sleep(0.5)
    stream(tracker, 1.0, 10.0)
    time.sleep(2.0)  # silent: said once it lasts max(0.5 s, twice the 33 ms period)
    assert service.status().input.silent
    flags = ("--base-frame", "cam", "--once", "-e", ep, *LOOPBACK_FLAGS)
    with running_cli("watch", *flags, env={"COLUMNS": "100"}) as proc:
        assert proc.wait(timeout=30) == 0
        shown = proc.stdout.read()
    assert "ann" in shown and "input silent for" in shown, shown
    assert "1 person held as last heard, not current" in " ".join(shown.split())


@pytest.mark.slow
def test_the_page_says_the_input_is_silent_and_when_it_is_heard_again(net):
    _, ep = net.service(silent_after_s=0.5, hold_silent_s=30.0)
    tracker = net.client(ep)
    client = FacingClient("hri", "cam", session_config=loopback_config(connect=[ep]))
    client.open()
    stop, ready, url = threading.Event(), threading.Event(), []
    page = threading.Thread(
        target=run_view,
        args=(
            client,
            "cam",
            "127.0.0.1",
            free_port(),
            stop,
            lambda u: (url.append(u), ready.set()),
        ),
    )
    page.start()
    browser = Browser(width=1000, height=700)
    try:
        assert ready.wait(10)
        browser.open(url[0])
        next_s = stream(tracker, 1.0, 10.0)
        browser.wait_for("document.querySelectorAll('g.person').length === 1")
        browser.wait_for("document.getElementById('connection').className === 'held'", 10)
        text = browser.evaluate("document.getElementById('connection').textContent")
        assert "input silent for" in text and "1 person held" in text, text
        stream(tracker, 1.5, next_s)  # heard again: the page says so
        browser.wait_for("document.getElementById('connection').className === 'connected'", 10)
    finally:
        browser.close()
        stop.set()
        page.join(10)
        client.close()
