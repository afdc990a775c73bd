"""The watch view, the one-command demo, and the examples, as their users run them."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
import time
from pathlib import Path

import pytest
from rich.console import Console

from facing_service.arguments import build_parser
from facing_service.client.watch import (
    ENGAGEMENT_LEGENDS,
    LEGEND,
    PersonView,
    arrow,
    fitted,
    render,
)
from facing_service.testing import LOOPBACK_FLAGS, running_cli

from loopback import endpoint, free_port, send, wait_until_answered
from poses import pose_json
from system_packages import require

pytestmark = pytest.mark.slow  # processes, recordings or seconds-long scenarios


ROOT = Path(__file__).resolve().parents[2]


def text_of(renderable) -> str:
    console = Console(width=120, record=True, color_system=None)
    console.print(renderable)
    return console.export_text()


def test_render_draws_people_where_they_stand_and_tabulates_them():
    people = [
        PersonView("alice", 2.0, 0.0, 180.0, True, 4.0, 2.0, 20.0, 3.5),  # ahead, facing the robot
        PersonView("bob", 0.0, 2.0, 90.0, False, 180.0, 2.0, 20.0, 1.0),  # on the left, turned away
        PersonView("carol", -1.0, -1.0, 0.0, False, None, None, 20.0, None),  # degenerate angle
    ]
    text = text_of(render(people, "base_link"))
    lines = text.splitlines()
    robot_row = next(i for i, line in enumerate(lines) if "R" in line and "│" in line)
    robot_col = lines[robot_row].index("R")
    # alice: 2 m ahead (up), on the robot's column, labelled because she faces it
    alice_row = next(i for i, line in enumerate(lines) if "↓alice" in line)
    assert alice_row < robot_row and lines[alice_row].index("↓") == robot_col
    # bob: 2 m to the left, on the robot's row, heading +y (left), labelled too (in yellow)
    assert "←bob" in lines[robot_row][:robot_col]
    assert "held s: how long the facing decision has held" in text  # the screen explained
    assert "1 of 3 facing the robot" in text
    assert re.search(r"alice\s*│\s*yes\s*│\s*4\.0\s*│\s*2\.00\s*│\s*3\.5", text)
    assert re.search(r"bob\s*│\s*no\s*│\s*180\.0", text)
    assert re.search(r"carol\s*│\s*no\s*│\s*-", text)


def test_an_empty_frame_says_which_frames_have_people():
    """watch defaulted to base_link against a service on camera_link and said "0 of 0
    facing" with no hint; now it names the frames that have people, and the flag."""
    text = text_of(render([], "base_link", elsewhere={"camera_link": 4, "base_link": 0}))
    assert "nobody in frame base_link; people are tracked in camera_link (4)" in text
    assert "watch --base-frame camera_link" in text
    assert "people are tracked" not in text_of(render([], "base_link", elsewhere={}))


def test_arrows_follow_the_heading():
    assert [arrow(a) for a in (0, 45, 90, 135, 180, -135, -90, -45, 359)] == list("↑↖←↙↓↘→↗↑")


def test_watch_once_shows_a_known_scene(net):
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link")
    tracker = net.client(endpoint(port))
    wait_until_answered(tracker, "hri/facing/base_link")
    flags = ("--once", "--wait-s", "2", "-e", endpoint(port), *LOOPBACK_FLAGS)
    with running_cli("watch", *flags) as watcher:
        # a tracker streams until the view is done: whenever it has subscribed (its start
        # takes seconds on a loaded machine), it sees the scene
        sec = 0
        while watcher.poll() is None and sec < 300:
            sec += 1
            ann = pose_json("ann", "base_link", x=2.0, y=1.0, off_deg=5.0, sec=sec)
            ben = pose_json("ben", "base_link", x=-1.5, y=0.5, yaw_deg=90.0, sec=sec)
            send(tracker, "hri/bodies/ann/pose/base_link", ann)
            send(tracker, "hri/bodies/ben/pose/base_link", ben)
            time.sleep(0.1)
        out, _ = watcher.communicate(timeout=30)
    assert watcher.returncode == 0, out
    assert "1 of 2 facing the robot" in out
    assert re.search(r"ann\s*│\s*yes\s*│\s*5\.0\s*│\s*2\.24", out), out
    assert re.search(r"ben\s*│\s*no", out), out


def test_watch_into_a_pipe_writes_frames_as_it_goes(net):
    """A defect found: ``watch > file`` (rich's live display, no terminal) wrote nothing until it
    exited. Into a pipe, its frames come while it runs, each whole."""
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link")
    tracker = net.client(endpoint(port))
    wait_until_answered(tracker, "hri/facing/base_link")
    with running_cli("watch", "-e", endpoint(port), *LOOPBACK_FLAGS) as watcher:
        assert watcher.stdout is not None
        lines: list[str] = []
        sec = 0
        while not any("1 of 1 facing the robot" in line for line in lines):
            sec += 1
            send(tracker, "hri/bodies/ann/pose/base_link",
                 pose_json("ann", "base_link", x=2.0, sec=sec))  # fmt: skip
            lines.append(watcher.stdout.readline())
            assert lines[-1] and sec < 600, "".join(lines)
        assert watcher.poll() is None  # still running: written as it goes


def test_demo_runs_alone_and_shows_someone_facing_the_robot():
    proc = subprocess.run(
        [sys.executable, "-m", "facing_service", "demo", "--duration-s", "3"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    # the view was drawn, with the simulated people in it (poses reach the view too)
    assert re.search(r"\d+ of [1-9]\d* facing the robot \(R\)", proc.stdout), proc.stdout
    assert re.search(r"p\d+\s*│\s*(yes|no)\s*│", proc.stdout), proc.stdout
    match = re.search(r"faced the robot during the demo: (.+)", proc.stdout)
    assert match and match.group(1) != "nobody", proc.stdout[-2000:]
    # it says where it answers, as a command that joins it
    joined = re.search(
        r"another view or your code can join it: facing-service (watch .+)", proc.stdout
    )
    assert joined, proc.stdout[:2000]
    build_parser().parse_args(shlex.split(joined[1]))


def run_example(name: str, port: int, seconds: float) -> subprocess.Popen:
    return subprocess.Popen(
        [
            sys.executable,
            str(ROOT / "examples" / name),
            "-e",
            endpoint(port),
            "--duration-s",
            str(seconds),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )


def test_examples_against_a_simulated_scene(net):
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link", stale_after_s=1.0)
    printer = run_example("facing_printer.py", port, 6)
    greeter = run_example("greeter.py", port, 6)
    try:
        time.sleep(1.0)  # let both clients connect before people appear
        with running_cli(
            "simulate",
            "-e",
            endpoint(port),
            *LOOPBACK_FLAGS,
            "--people",
            "5",
            "--seed",
            "0",
            "--duration-s",
            "4",
        ) as sim:
            sim.wait(timeout=30)
        printed, _ = printer.communicate(timeout=30)
        greeted, _ = greeter.communicate(timeout=30)
    finally:
        for proc in (printer, greeter):
            if proc.poll() is None:
                proc.kill()
    lines = [line for line in printed.splitlines() if line.startswith("facing the robot:")]
    assert 5 <= len(lines) <= 7  # once a second
    assert any(re.fullmatch(r"facing the robot: (p\d+ ?)+", line) for line in lines), printed
    hellos = re.findall(r"hello (p\d+)! \(at \d+\.\d m\)", greeted)
    assert hellos, greeted
    assert len(hellos) == len(set(hellos)), "greeted someone twice without a goodbye"
    goodbyes = re.findall(r"goodbye (p\d+)", greeted)
    assert set(goodbyes) <= set(hellos)  # goodbye only to people greeted
    assert goodbyes, "stale_after_s=1: everyone is lost after the scene ends"


def test_watch_lists_what_the_service_says_on_ros2_input(net):
    """On ROS 2 input there are no JSON poses: people are drawn from the service's results
    (their position and heading), as on any input (they were only listed before)."""
    from facing_service.client.client import FacingClient
    from facing_service.client.watch import Watcher
    from facing_service.tools.loopback import loopback_config

    import rmw_zenoh
    from ros_messages import S, ids_list, tf_message, transform, yaw_q

    router = net.router()
    ep = endpoint(router.port)
    net.robot_service(ep, base_frame="base_link")
    robot = rmw_zenoh.Robot(net.client(ep, mode="client"), rmw_zenoh.JAZZY_0_2_10)
    config = loopback_config(connect=[ep], mode="client")
    try:
        with FacingClient("hri", "base_link", session_config=config) as client:
            watcher = Watcher(client, "base_link")
            for i in range(45):
                robot.publish("/humans/bodies/tracked", "hri_msgs/msg/IdsList", ids_list(["a"]))
                body = transform("base_link", "body_a", S + i * S // 30, (2.0, 0, 0), yaw_q(180))
                robot.publish("/tf", "tf2_msgs/msg/TFMessage", tf_message(body))
                time.sleep(1 / 30)
            time.sleep(0.3)
            text = text_of(watcher.view())
    finally:
        robot.close()
    assert "1 of 1 facing the robot" in text and "not drawn" not in text
    assert "↓body_a" in text  # 2 m ahead, facing the robot (down the screen)
    # held: 44 frames of pose time (1.47 s), exactly: body_a appeared after the view opened
    assert re.search(r"body_a\s*│\s*yes\s*│\s*0\.0\s*│\s*2\.00\s*│\s*1\.5", text), text


def test_held_is_at_least_only_for_people_there_before_the_view(net):
    """A defect found: "≥" (already so when the view started) was said of people who appeared
    after the view started too: their first result is when their decision began."""
    from facing_service.client.client import FacingClient
    from facing_service.client.watch import Watcher
    from facing_service.tools.loopback import loopback_config

    _, ep = net.service(base_frame="base_link")
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/facing/base_link")
    key = "hri/bodies/{}/pose/base_link"
    send(tracker, key.format("early"), pose_json("early", "base_link", off_deg=5.0, sec=1))
    wait_until_answered(tracker, "hri/bodies/early/facing/base_link")
    with FacingClient("hri", "base_link", session_config=loopback_config(connect=[ep])) as c:
        watcher = Watcher(c, "base_link")
        for sec in (2, 3, 4):
            for who in ("early", "late"):
                send(tracker, key.format(who), pose_json(who, "base_link", off_deg=5.0,
                                                         sec=sec))  # fmt: skip
        deadline = time.monotonic() + 5
        while not re.search(r"late\s*│.*│\s*2\.0\s*│", text := text_of(watcher.view())):
            assert time.monotonic() < deadline, text
            time.sleep(0.05)
    assert re.search(r"early\s*│\s*yes\s*│.*│\s*≥2\.0\s*│", text), text
    assert re.search(r"late\s*│\s*yes\s*│.*│\s*2\.0\s*│", text), text


def test_where_to_stand_prints_the_places_to_join_and_to_greet(net):
    """The example of the docs: a pair talking 3 m ahead, a person engaging 2.4 m behind: where
    to join the pair, where to greet the person."""
    port = free_port()
    net.service(listen=[endpoint(port)], base_frame="base_link", group_hold_s=0.2)
    tracker = net.client(endpoint(port))
    wait_until_answered(tracker, "hri/facing/base_link")
    people = {
        "ann": dict(x=3.0, y=0.6, yaw_deg=-90.0),
        "bob": dict(x=3.0, y=-0.6, yaw_deg=90.0),
        "cy": dict(x=-2.4, y=0.0, yaw_deg=0.0),  # faces the robot from behind it
    }
    example = run_example("where_to_stand.py", port, 6)
    try:
        for second in range(1, 6):
            for name, where in people.items():
                send(tracker, f"hri/bodies/{name}/pose/base_link",
                     pose_json(name, "base_link", sec=second, **where))  # fmt: skip
            time.sleep(1.0)
        printed, _ = example.communicate(timeout=30)
    finally:
        if example.poll() is None:
            example.kill()
    assert re.search(
        r"to join ann, bob: stand at \((2|1)\.\d\d, -?0\.\d\d\) facing -?\d°", printed
    ), printed
    assert re.search(r"to greet cy: stand at \(-1\.20, -?0\.00\) facing -?180°", printed), printed


def test_the_demo_fits_an_80x24_terminal_as_a_person_sees_it(tmp_path):
    """A defect found: on 80x24 the demo showed the radar and only the table's header, then
    "...". Run in a real terminal (tmux) of that size: every person's row is on screen."""
    require("tmux")
    session = f"facing-demo-{os.getpid()}"
    command = shlex.join([sys.executable, "-m", "facing_service", "demo", "--duration-s", "20",
                          "--view-port", "0"])  # fmt: skip
    subprocess.run(["tmux", "new-session", "-d", "-s", session, "-x", "80", "-y", "24",
                    f"cd {shlex.quote(str(ROOT))} && {command}"], check=True)  # fmt: skip
    try:
        deadline, screen = time.monotonic() + 20, ""
        while time.monotonic() < deadline:
            time.sleep(0.5)
            screen = subprocess.run(["tmux", "capture-pane", "-p", "-t", session],
                                    capture_output=True, text=True).stdout  # fmt: skip
            if len(re.findall(r"^\s*│?\s*p\d+\s", screen, re.M)) == 5:
                break  # (ids go on as people leave and others come: p6, p7, ...)
    finally:
        subprocess.run(["tmux", "kill-session", "-t", session], capture_output=True)
    rows = re.findall(r"^\s*│?\s*(p\d+)\s", screen, re.M)
    assert len(set(rows)) == 5, screen  # five people, each a row
    assert "R" in screen and "facing the robot (R)" in screen, screen
    assert len(screen.rstrip("\n").splitlines()) <= 24


@pytest.mark.parametrize(("columns", "lines"), [(80, 24), (100, 40), (64, 24), (200, 60)])
def test_the_view_fits_the_terminal_with_every_row(columns: int, lines: int):
    people = [PersonView(f"p{i}", 1.0 + i * 0.3, 0.5, 180.0, i % 2 == 0, 4.0, 2.0, 20.0, 1.0)
              for i in range(1, 6)]  # fmt: skip
    drawn: list[tuple[int, int, str | None]] = []

    def draw(width: int, height: int, legend: str | None):
        drawn.append((width, height, legend))
        return render(people, "base_link", width=width, height=height, legend=legend)

    console = Console(width=columns, height=lines, record=True, color_system=None)
    console.print(fitted(draw, LEGEND + ENGAGEMENT_LEGENDS["rule"], columns, lines))
    printed = console.export_text().rstrip("\n").splitlines()
    assert len(printed) <= lines - 1, "\n".join(printed)  # Live keeps a line
    assert all(any(f"p{i} " in line for line in printed) for i in range(1, 6)), printed
    width, height, legend = drawn[-1]
    assert height % 2 == 1 and 7 <= height <= 19 and width <= columns
    assert (legend is not None) == (lines >= 40), (columns, lines, drawn)
    assert ("hri_engagement's rule" in "\n".join(printed)) == (legend is not None)


@pytest.mark.parametrize(
    ("mode", "said"),
    [("rule", "engagement is hri_engagement's rule"), ("service", "needs more than facing")],
)
def test_the_legend_explains_the_engagement_mode_the_service_runs(net, mode: str, said: str):
    """A defect found: with --engagement rule, watch's footer still explained the default mode."""
    from facing_service.client.client import FacingClient
    from facing_service.client.watch import Watcher
    from facing_service.tools.loopback import loopback_config

    _, ep = net.service(base_frame="base_link", engagement=mode)
    with FacingClient("hri", "base_link", session_config=loopback_config(connect=[ep])) as c:
        watcher = Watcher(c, "base_link")
        watcher.ask_frames()
        text = " ".join(text_of(watcher.view()).split())
    assert said in text, text
