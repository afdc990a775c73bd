"""The plain-zenoh examples (one program per operation, as zenoh's own): a tracker's
poses, a subscriber, a get and a status read, each run as a user runs it against a live
service. The FacingClient examples run in test_watch_demo."""

from __future__ import annotations

import re
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

from loopback import endpoint, free_port, get, results, send, wait_until, wait_until_answered
from poses import pose_json

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
    assert re.search(r"^published \d+ poses, (\d+) heard by a subscriber; ann and bob deleted$",
                     published, re.M), published  # fmt: skip
    assert re.search(r"^ann: facing=True angle=\d+°$", answered, re.M), answered
    assert re.search(r"^bob: facing=False angle=\d+°$", answered, re.M), answered
    assert re.search(
        r"^front: ok, facing-service \S+, 2 bodies, \d+ poses accepted$", said, re.M
    ), said
    assert re.search(r"^ann faces the robot \(2\.\d m\)$", heard, re.M), heard
    assert re.search(r"^bob looks elsewhere \(3\.\d m\)$", heard, re.M), heard
    assert "hri/bodies/ann/facing/base_link: lost" in heard, heard
    assert all(proc.returncode == 0 for proc in procs)


def test_with_no_service_each_example_says_so_and_fails():
    """A defect found: publishing to nowhere said "published", a query and a subscriber nobody
    answered printed nothing; each exited 0."""
    port = free_port()  # nothing listens there
    runs = {
        "tracker.py": ("--duration-s", "1"),
        "query.py": (),
        "subscribe.py": ("--duration-s", "2.5"),
        "status.py": (),
    }
    procs = {name: example(name, port, *flags) for name, flags in runs.items()}
    said = {name: proc.communicate(timeout=30)[0] for name, proc in procs.items()}
    assert all(proc.returncode == 1 for proc in procs.values()), said
    assert (
        "0 heard by a subscriber" in said["tracker.py"]
        and "no subscriber heard" in said["tracker.py"]
    )
    assert "no facing service answered hri/bodies/*/facing/base_link" in said["query.py"]
    assert "heard no result" in said["subscribe.py"]
    assert "no facing service answered its status" in said["status.py"]
    assert not any("Traceback" in out for out in said.values()), said


def loading_zenoh(proc: subprocess.Popen[str]) -> None:
    """Return once ``proc`` has mapped zenoh's native library: it is inside its imports
    (zenoh's, then the client's), past the interpreter's start, whose Ctrl-C is Python's
    own (a traceback no program can prevent) and which a loaded machine stretches past
    any fixed delay (seen in CI)."""
    maps = Path(f"/proc/{proc.pid}/maps")
    deadline = time.monotonic() + 30
    while "zenoh" not in maps.read_text():
        assert proc.poll() is None and time.monotonic() < deadline, "zenoh never loaded"
        time.sleep(0.002)


def test_ctrl_c_ends_every_example_quietly_and_the_tracker_deletes_its_people(net):
    """A defect found: Ctrl-C printed a traceback (during the imports too), and the tracker then
    never sent the DELETEs its docs promise."""
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link")
    lost = net.recorder(net.client(endpoint(port)), "hri/bodies/*/pose/base_link")
    for name in ("facing_printer.py", "greeter.py", "where_to_stand.py", "tracker.py"):
        for during_imports in (True, False):
            proc = example(name, port)
            if during_imports:
                loading_zenoh(proc)
            elif name == "tracker.py":  # once it has people to delete, and knows it is
                # heard (zenoh's matching status comes a moment after the first put:
                # interrupted at once, it said "no subscriber heard them", seen in CI)
                lost.wait_for(lambda item: item.kind == "put", count=20, timeout=30)
            else:
                time.sleep(2.5)
            proc.send_signal(signal.SIGINT)
            out, _ = proc.communicate(timeout=30)
            assert proc.returncode == 0 and "Traceback" not in out, (name, during_imports, out)
    # the run stopped in its imports published nobody; the other deletes the two it did
    deletes = lost.wait_for(lambda item: item.kind == "delete", count=2)
    assert {item.key for item in deletes} == {
        "hri/bodies/ann/pose/base_link",
        "hri/bodies/bob/pose/base_link",
    }


def test_a_ctrl_c_pending_from_the_imports_ends_an_example_quietly():
    """A Ctrl-C that arrived while the imports loaded is raised by the very switch of
    handlers in ``run`` (seen in CI: a KeyboardInterrupt traceback from
    ``signal.signal``); it must end the example as quietly as one inside ``main``."""
    script = (
        "import signal, sys; sys.path.insert(0, sys.argv[1]); import common\n"
        "def pending(*_): raise KeyboardInterrupt\n"
        "common.signal.signal = pending\n"
        "common.run(lambda: 3)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script, str(EXAMPLES)], capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr


def test_the_subscriber_prints_a_body_straight_below_the_robot(net):
    """A defect found: ``distance_m`` is null when the robot is straight above a
    person (the README says so) and subscribe.py formatted it with ``:.1f``: a traceback
    on the first such result. (This is its test.)"""
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link")
    subscriber = example("subscribe.py", port, "--duration-s", "4")
    try:
        time.sleep(1.5)  # the subscriber meets the service before the pose comes
        tracker = net.client(endpoint(port))
        wait_until_answered(tracker, "hri/facing/base_link")
        send(tracker, "hri/bodies/under/pose/base_link",
             pose_json("under", "base_link", x=0.0, y=0.0, yaw_deg=0.0))  # fmt: skip
        heard, _ = subscriber.communicate(timeout=30)
    finally:
        if subscriber.poll() is None:
            subscriber.kill()
    assert "Traceback" not in heard, heard
    assert re.search(r"^under looks elsewhere$", heard, re.M), heard


def test_a_subscriber_piped_into_head_ends_quietly_when_head_has_its_lines(net):
    """A defect found: ``examples/subscribe.py | head`` flooded the terminal with BrokenPipeError
    tracebacks, one from each result's callback after head ended."""
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link")
    pipeline = (
        f"{shlex.quote(sys.executable)} {shlex.quote(str(EXAMPLES / 'subscribe.py'))} "
        f"-e {endpoint(port)} --duration-s 20 | head -n 3"
    )
    shell = subprocess.Popen(
        ["bash", "-o", "pipefail", "-c", pipeline],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    tracker = example("tracker.py", port, "--duration-s", "20")
    try:
        out, err = shell.communicate(timeout=60)
    finally:
        tracker.kill()
        tracker.communicate()
    assert len(out.splitlines()) == 3, out
    assert "Traceback" not in err and "BrokenPipeError" not in err, err
    assert shell.returncode == 0, err  # the subscriber itself ended with 0, well before 20 s


def test_a_get_before_any_pose_says_nobody_is_there_and_succeeds(net):
    """A defect found: two services in a namespace, neither with a pose yet: query.py printed
    "refused: empty_frame" and "refused: unknown_frame" and exited 0. A room with nobody
    in it yet is no refusal; a frame no service knows while others are tracked still is."""
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link", instance="fixed")
    _, other = net.service(base_frame="*", instance="any", connect=[endpoint(port)])
    empty = example("query.py", port)
    said, _ = empty.communicate(timeout=30)
    assert empty.returncode == 0 and said == "nobody in frame base_link now\n", said
    tracker = net.client(other)
    wait_until_answered(tracker, "hri/services/facing/any/status")
    send(tracker, "hri/bodies/ann/pose/cam", pose_json("ann", "cam"))
    wait_until(lambda: results(get(tracker, "hri/bodies/ann/facing/cam")), 10, "ann tracked")
    typo = example("query.py", port, "--base-frame", "cma")
    said, _ = typo.communicate(timeout=30)
    assert typo.returncode == 1 and said.count("refused: unknown_frame") == 2, said
