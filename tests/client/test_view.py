"""The live page, as a person sees it: Debian's headless chromium loads it
against a live service fed like a tracker, and reads what is drawn and written."""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path

import pytest

from facing_service.client.client import FacingClient
from facing_service.client.view.live import run_view
from facing_service.client.view.server import serve
from facing_service.client.view.snapshot import MAX_DRAWN
from facing_service.testing import free_port

from browser import Browser
from loopback import endpoint, loopback_config, send
from poses import pose_json

pytestmark = pytest.mark.slow  # a browser, a router, services

NAMESPACE = "hri"
#: Set to a path (docs/view.png) to save the screenshot the docs and README show.
SCREENSHOT = os.environ.get("FACING_TEST_VIEW_SCREENSHOT")


class Page:
    """A view server on a thread, until closed."""

    def __init__(self, target, *args) -> None:
        self.stop = threading.Event()
        self.url: str | None = None
        ready = threading.Event()

        def started(url: str) -> None:
            self.url = url
            ready.set()

        self.thread = threading.Thread(target=target, args=(*args, self.stop, started))
        self.thread.start()
        assert ready.wait(10), "the view server did not start"

    def close(self) -> None:
        self.stop.set()
        self.thread.join(10)


@pytest.fixture
def browser():
    chromium = Browser(width=1200, height=720)
    yield chromium
    chromium.close()


def level_of(browser: Browser, person: str) -> str | None:
    return browser.evaluate(
        f"document.querySelector('g.person[data-id=\"{person}\"]')?.dataset.level ?? null"
    )


def test_the_page_draws_the_scene_and_says_when_the_service_is_lost(net, browser):
    router = net.router()
    ep = endpoint(router.port)
    service, _ = net.service(mode="client", connect=[ep], listen=[], group_hold_s=0.1)
    tracker = net.client(ep, mode="client")
    client = FacingClient(
        NAMESPACE, "cam", session_config=loopback_config(connect=[ep], mode="client")
    )
    client.open()
    port = free_port()
    page = Page(run_view, client, "cam", "127.0.0.1", port)
    try:
        browser.open(page.url)
        # ann and bob talk beside the robot; cat faces it long enough to engage
        for i in range(75):
            sec, nanosec = divmod(round((10 + i / 30) * 1e9), 1_000_000_000)
            stamp = {"sec": sec, "nanosec": nanosec}
            send(
                tracker,
                f"{NAMESPACE}/bodies/ann/pose/cam",
                pose_json("ann", "cam", x=3.0, y=2.0, yaw_deg=0.0, **stamp),
            )
            send(
                tracker,
                f"{NAMESPACE}/bodies/bob/pose/cam",
                pose_json("bob", "cam", x=4.2, y=2.0, yaw_deg=180.0, **stamp),
            )
            send(tracker, f"{NAMESPACE}/bodies/cat/pose/cam",
                 pose_json("cat", "cam", x=1.5, y=-0.8, **stamp))  # fmt: skip
        browser.wait_for("document.querySelectorAll('g.person').length === 3")
        browser.wait_for(
            "document.querySelector('g.person[data-id=\"cat\"]')?.dataset.level === 'ENGAGED'"
        )
        colours = browser.evaluate(
            "[...document.querySelectorAll('g.person')].map(g => [g.dataset.level,"
            " g.querySelector('circle').getAttribute('fill')])"
        )
        palette = {"ENGAGED": "#22aa22", "ENGAGING": "#e6a800", "DISENGAGING": "#e6a800",
                   "DISENGAGED": "#dd2222", "UNKNOWN": "#999999"}  # fmt: skip
        assert all(palette[level] == fill for level, fill in colours), colours
        # two groups: ann and bob, and cat with the robot she faces 1.7 m away (a pair
        # farther apart than 2 m, twice the longest stride, is no ring with the robot)
        browser.wait_for("document.querySelectorAll('g.group').length === 2")
        assert (
            browser.evaluate("document.querySelectorAll('g.group[data-robot=\"true\"]').length")
            == 1
        )
        text = browser.wait_for(
            "document.body.innerText.includes('group') && document.body.innerText"
        )
        assert "ann, bob" in text and "cat and the robot" in text and "connected" in text
        # where the robot should stand to join ann and bob: drawn, and said
        browser.wait_for("document.querySelectorAll('g.join').length === 1")
        assert browser.wait_for("document.getElementById('groups').innerText.includes('join at (')")
        assert browser.evaluate("document.querySelectorAll('line.gaze').length") >= 2
        if SCREENSHOT:
            Path(SCREENSHOT).write_bytes(b"")  # the path is writable before the browser tries
            browser.screenshot(Path(SCREENSHOT))
        # the service goes: the page says so; another comes: the page recovers by itself
        service.close()
        browser.wait_for(
            "document.getElementById('connection').textContent.includes('disconnected')"
        )
        net.service(mode="client", connect=[ep], listen=[])
        browser.wait_for("document.getElementById('connection').className === 'connected'")
        # the view itself goes and comes back on its port: the page reconnects by itself
        page.close()
        browser.wait_for(
            "document.getElementById('connection').textContent.includes('not reachable')"
        )
        page = Page(run_view, client, "cam", "127.0.0.1", port)
        browser.wait_for("document.getElementById('connection').className === 'connected'", 15)
    finally:
        page.close()
        client.close()


def test_ids_are_shown_as_text_and_a_crowd_renders_bounded(browser):
    """The service refuses such ids at intake (names are [A-Za-z0-9_.-]); the page must
    not trust that: an id full of markup is shown as text and never runs."""
    evil = '<img src=x onerror="window.pwned=1"><script>window.pwned=1</script>'
    person = {
        "id": evil,
        "x": 2.0,
        "y": 0.0,
        "heading_deg": 180.0,
        "facing": True,
        "angle_deg": 0.0,
        "distance_m": 2.0,
        "threshold_deg": 20.0,
        "level": "ENGAGED",
    }
    crowd = [dict(person, id=f"p{i}", x=3.0 + i % 50, y=i // 50) for i in range(MAX_DRAWN - 1)]
    model = {"frame": "cam", "service": "live", "people": [person, *crowd], "not_drawn": 4801,
             "groups": [], "gazing": [], "elsewhere": {}}  # fmt: skip
    page = Page(serve, lambda: model, "127.0.0.1", free_port())
    try:
        browser.open(page.url)
        browser.wait_for(f"document.querySelectorAll('g.person').length === {MAX_DRAWN}")
        assert browser.evaluate("document.querySelector('#people td').textContent") == evil
        assert browser.evaluate("document.querySelector('text.label').textContent") == evil
        assert browser.evaluate(
            "window.pwned === undefined && !document.querySelector('#people img')"
        )
        assert "4801 more people not drawn" in browser.evaluate("document.body.innerText")
    finally:
        page.close()


def test_labels_of_people_standing_close_do_not_overlap(browser):
    """A defect found: two people 10 cm apart had their names drawn over each other."""
    person = {"x": 2.0, "y": 0.0, "heading_deg": 180.0, "facing": True, "angle_deg": 0.0,
              "distance_m": 2.0, "threshold_deg": 20.0, "level": "ENGAGED"}  # fmt: skip
    close = [dict(person, id=f"person_long_name_{i}", y=0.05 * i) for i in range(3)]
    model = {"frame": "cam", "service": "live", "people": close, "not_drawn": 0,
             "groups": [], "gazing": [], "elsewhere": {}}  # fmt: skip
    page = Page(serve, lambda: model, "127.0.0.1", free_port())
    try:
        browser.open(page.url)
        browser.wait_for("document.querySelectorAll('text.label').length === 3")
        boxes = browser.evaluate(
            "JSON.stringify([...document.querySelectorAll('text.label')].map((t) => {"
            " const b = t.getBBox(); return [b.x, b.y, b.width, b.height, t.textContent]; }))"
        )
        labels = json.loads(boxes)
        assert sorted(b[4] for b in labels) == [f"person_long_name_{i}" for i in range(3)]
        for i, a in enumerate(labels):
            for b in labels[i + 1 :]:
                apart = (a[0] + a[2] <= b[0] or b[0] + b[2] <= a[0]
                         or a[1] + a[3] <= b[1] + 1e-6 or b[1] + b[3] <= a[1] + 1e-6)  # fmt: skip
                assert apart, (a, b)
    finally:
        page.close()


def test_a_person_close_to_the_robot_is_drawn_apart_from_it_and_their_group(browser):
    """A defect found: at 0.6 m (a face in front of a laptop's camera) the robot, the face's
    label and the group's circle were drawn over each other on a 4 m radar."""
    person = {
        "id": "f1",
        "x": 0.6,
        "y": 0.0,
        "heading_deg": 180.0,
        "facing": True,
        "angle_deg": 0.0,
        "distance_m": 0.6,
        "threshold_deg": 20.0,
        "level": "ENGAGED",
    }
    group = {
        "id": "1",
        "members": ["f1"],
        "robot": True,
        "centre": {"x": 0.3, "y": 0.0},
        "join": None,
    }
    model = {"frame": "base_link", "service": "live", "people": [person], "not_drawn": 0,
             "groups": [group], "gazing": [], "elsewhere": {}}  # fmt: skip
    page = Page(serve, lambda: model, "127.0.0.1", free_port())
    try:
        browser.open(page.url)
        browser.wait_for("document.querySelectorAll('text.label').length === 1")
        marks = json.loads(browser.evaluate(
            "JSON.stringify(['polygon.robot', 'g.group circle', 'g.person circle', 'text.label',"
            " 'text.robot-label'].map((s) => { const b = document.querySelector(s)"
            ".getBoundingClientRect(); return [s, b.left, b.top, b.right, b.bottom]; }))"
        ))  # fmt: skip
    finally:
        page.close()
    for i, (a, *ra) in enumerate(marks):
        for b, *rb in marks[i + 1 :]:
            apart = ra[2] <= rb[0] or rb[2] <= ra[0] or ra[3] <= rb[1] or rb[3] <= ra[1]
            assert apart, (a, ra, b, rb)
