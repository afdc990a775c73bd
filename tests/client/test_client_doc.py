"""docs/client.md as a user reads it: every snippet runs, in order, against a live
service with three people, and every ``# -> `` line is what it prints; every public
method of FacingClient appears in a snippet."""

from __future__ import annotations

import contextlib
import inspect
import io
import re
import threading
from collections.abc import Iterator
from pathlib import Path

import zenoh

from facing_service import FacingClient

from loopback import get, send, wait_until, wait_until_answered
from poses import pose_json

DOC = Path(__file__).resolve().parents[2] / "docs" / "client.md"
#: ann faces the robot from the social zone; bob and cat face each other.
PEOPLE = {"ann": (3.0, 0.0, 180.0), "bob": (3.0, 1.5, 90.0), "cat": (3.0, 2.3, -90.0)}


def snippets() -> list[str]:
    section = DOC.read_text().split("## Using it from Python", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, re.S)


@contextlib.contextmanager
def people(tracker: zenoh.Session) -> Iterator[None]:
    """Three people at 30 Hz on the tracker's clock, for as long as the doc runs."""
    stop = threading.Event()

    def publish() -> None:
        tick = 0
        while not stop.is_set():
            sec, nanosec = divmod(100 * 30 + tick, 30)
            for body, (x, y, yaw) in PEOPLE.items():
                pose = pose_json(body, "base_link", x=x, y=y, yaw_deg=yaw, sec=sec,
                                 nanosec=nanosec * 33_333_333)  # fmt: skip
                send(tracker, f"hri/bodies/{body}/pose/base_link", pose)
            tick += 1
            stop.wait(0.0 if tick < 120 else 1 / 30)  # 4 s at once, then live

    thread = threading.Thread(target=publish, daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join(2)


def test_every_public_method_is_shown():
    shown = "\n".join(snippets())
    public = [n for n, _ in inspect.getmembers(FacingClient) if not n.startswith("_")]
    missing = [n for n in public if not re.search(rf"\.{n}\b", shown)]
    assert not missing, f"docs/client.md shows no snippet of {missing}"


def test_the_snippets_run_and_print_what_they_say(net):
    _, ep = net.service(base_frame="base_link", instance="front")
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/services/facing/*/status")
    code = "\n".join(snippets()).replace("tcp/192.168.1.10:7447", ep)
    said = [line.split("# -> ", 1)[1] for line in code.splitlines() if "# -> " in line]
    out = io.StringIO()
    with people(tracker):
        wait_until(lambda: _ready(tracker), 10, "ann ENGAGED and bob with cat")
        with contextlib.redirect_stdout(out):
            exec(compile(code, str(DOC), "exec"), {})  # the doc's own code
    printed = out.getvalue().splitlines()
    missing = [line for line in said if line not in printed]
    assert not missing, f"printed {printed}"


def _ready(tracker: zenoh.Session) -> bool:
    levels = {v["body_id"]: v["level"] for _, v in get(tracker, "hri/bodies/*/engagement/*")}
    groups = [g["members"] for _, v in get(tracker, "hri/groups/base_link") for g in v["groups"]]
    print(levels, groups)
    return levels.get("ann") == "ENGAGED" and groups == [["bob", "cat"]]
