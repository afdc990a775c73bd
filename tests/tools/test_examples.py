"""The plain-zenoh examples (one program per operation, as zenoh's own): a tracker's
poses, a subscriber, a get and a status read, each run as a user runs it against a live
service. The FacingClient examples run in test_watch_demo."""

from __future__ import annotations

import re
import subprocess
import sys
import time
from pathlib import Path

from loopback import endpoint, free_port

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def example(name: str, port: int, *flags: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, str(EXAMPLES / name), "-e", endpoint(port), *flags],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )


def test_a_tracker_a_subscriber_a_get_and_a_status_read(net):
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link", instance="front")
    subscriber = example("subscribe.py", port, "--duration-s", "8")
    procs = [subscriber]
    try:
        time.sleep(1.5)  # the subscriber meets the service before the poses come
        tracker = example("tracker.py", port, "--duration-s", "4")
        procs.append(tracker)
        time.sleep(2.0)
        asked = example("query.py", port, "--threshold-deg", "90")
        status = example("status.py", port)
        procs += [asked, status]
        answered, _ = asked.communicate(timeout=30)
        said, _ = status.communicate(timeout=30)
        published, _ = tracker.communicate(timeout=30)
        heard, _ = subscriber.communicate(timeout=30)
    finally:
        for proc in procs:
            if proc.poll() is None:
                proc.kill()
    assert published.strip() == "published", published
    assert re.search(r"^ann: facing=True angle=\d+°$", answered, re.M), answered
    assert re.search(r"^bob: facing=False angle=\d+°$", answered, re.M), answered
    assert re.search(
        r"^front: ok, facing-service \S+, 2 bodies, \d+ poses accepted$", said, re.M
    ), said
    assert re.search(r"^ann faces the robot \(2\.\d m\)$", heard, re.M), heard
    assert re.search(r"^bob looks elsewhere \(3\.\d m\)$", heard, re.M), heard
    assert "hri/bodies/ann/facing/base_link: lost" in heard, heard
    assert all(proc.returncode == 0 for proc in procs)
