"""``facing-service simulate``: people published as a body tracker would (JSON poses on
the service's keys), or with ``--ros2`` as a ROS 2 robot running ROS4HRI would (its own
topics, in CDR, on its router), until Ctrl-C or ``--duration-s``."""

from __future__ import annotations

import argparse
import sys
import threading
import time
from collections.abc import Callable

from ..client.presence import ServiceWatch
from ..client.sim import Crowd, TrackerPublisher, nobody_heard, simulate
from ..config.disclosure import public_endpoints
from ..config.profiles import robot_wire
from ..config.session import opened, zenoh_config
from ..config.settings import Settings
from ..contract import keys
from ..contract.words import for_how_long


def crowd_of(args: argparse.Namespace) -> Crowd:
    """The simulated people, stamped from now on: a second run against a long-lived
    service continues its clock (were every run to start at the same stamp, the next
    would be refused as out of order, read as a tracker's clock started over)."""
    return Crowd(people=args.people, seed=args.seed, start_s=time.time())


def simulate_command(
    args: argparse.Namespace, settings: Settings, stop: threading.Event, say: Callable[[str], None]
) -> int:
    """The command; ``say`` prints a progress line. Returns the exit code."""
    if args.ros2:
        return _robot(args, settings, stop)
    if args.record is not None:
        print("facing-service simulate: --record only with --ros2 (a ROS 2 bag holds a "
              "robot's topics; the JSON poses are not recorded)", file=sys.stderr)  # fmt: skip
        return 2
    key = keys.pose_key(settings.namespace, body_id="<id>", frame_id=args.base_frame)
    until = for_how_long(args.duration_s)
    print(f"simulating {args.people} people: poses on {key} at {args.rate_hz:g} Hz{until}")
    if (session := opened(zenoh_config(settings), "simulate")) is None:
        return 1
    watch = ServiceWatch(session, "simulate", settings.namespace, settings.connect, _warn)
    with session, watch:
        publish = TrackerPublisher(session, progress_every_s=5.0, say=say)
        try:
            ticks = simulate(
                publish,
                crowd_of(args),
                args.base_frame,
                settings.namespace,
                args.rate_hz,
                args.duration_s,
                should_stop=stop.is_set,
            )
        finally:
            publish.close()
    print(
        f"published {publish.poses} poses and {publish.deletes} deletes in {ticks} ticks, "
        f"{publish.heard} heard by a subscriber"
    )
    if publish.poses and not publish.heard:  # sent to nowhere: not a success
        print(nobody_heard("simulate", key, settings.namespace, settings.connect), file=sys.stderr)
        return 1
    return 0


def _robot(args: argparse.Namespace, settings: Settings, stop: threading.Event) -> int:
    """``simulate --ros2``: the robot's topics, and with ``--record`` its bag."""
    from .record import record_refusal  # rosbags: for the robot only
    from .robot_scene import RobotScene
    from .ros_robot import SimulatedRobot, recorded_line

    if args.record is not None and (refused := record_refusal(args.record)):
        print(f"facing-service simulate: {refused}", file=sys.stderr)
        return 2
    wire = robot_wire(settings)
    until = for_how_long(args.duration_s)
    print(f"simulating a ROS4HRI robot with {args.people} people in {wire.describe()}: /tf, "
          f"/tf_static and /humans/* at {args.rate_hz:g} Hz{until}", flush=True)  # fmt: skip
    if (session := opened(zenoh_config(settings), "simulate")) is None:
        return 1
    with session:
        robot = SimulatedRobot(session, wire, args.record)
        try:
            run = robot.play(
                RobotScene(crowd_of(args), args.base_frame),
                args.rate_hz,
                args.duration_s,
                stop.is_set,
            )
        finally:
            recorded = robot.close()
    print(f"published {run.messages} messages on {run.topics} topics in {run.ticks} ticks; "
          f"{run.persons} persons tracked")  # fmt: skip
    if recorded is not None:
        print(recorded_line(recorded, args.record))
    elif not run.heard:  # sent to nowhere, and kept nowhere: not a success
        endpoints = public_endpoints(settings.connect)
        where = f"reachable at {endpoints}" if endpoints else "found by scouting from here"
        print(f"facing-service simulate: no subscriber heard the robot's /tf: is a service "
              f"running with --input ros2 in the same --ros-format, domain and namespace, "
              f"{where}?", file=sys.stderr)  # fmt: skip
        return 1
    return 0


def _warn(line: str) -> None:
    print(line, file=sys.stderr, flush=True)
