"""The command line's grammar: every command, its flags and their checks. Each bad value
is refused in one line that names the flag; every ``run`` flag is also a ``FACING_<NAME>``
variable (what a container is configured with), and the zenoh flags are those of zenoh's
own example programs, so a zenoh user already knows them. What each command does is
``cli``'s.
"""

from __future__ import annotations

import argparse
from collections.abc import Iterable
from pathlib import Path
from typing import Any, Literal, NoReturn, get_args, get_origin

from .argument_types import (
    NON_NEGATIVE,
    POSITIVE,
    field_of_view,
    finite,
    id_prefix,
    listen_address,
    number,
    port_number,
)
from .config.fields import SERVICE, ZENOH
from .config.settings import Settings
from .config.sources import env_help, env_name, flag_info, flag_name, shown_default
from .config.version import VERSION


class _Parser(argparse.ArgumentParser):
    """One line for a bad argument, naming it (argparse would print the whole usage
    first); no abbreviated flags (``--threshold 30`` is not ``--threshold-deg 30``)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **{**kwargs, "allow_abbrev": False})
        self.commands: dict[str, argparse.ArgumentParser] = {}  # the top level's commands

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: {message} (see {self.prog} --help)\n")


#: The zenoh session's settings: the flags of zenoh's own example programs.
ZENOH_FIELDS = tuple(f for f in Settings.model_fields if flag_info(f)["group"] == ZENOH)


def add_zenoh_arguments(parser: argparse.ArgumentParser) -> None:
    """The session flags every zenoh example program takes."""
    add_settings_arguments(parser, ZENOH_FIELDS)


def add_settings_arguments(parser: argparse.ArgumentParser, fields: Iterable[str]) -> None:
    """One flag per setting, generated from ``Settings``: its name, type, choices, help
    (the field's description, its variable and default) and group. The service's flags
    and docs/configuration.md's table come from the same fields."""
    groups: dict[str, argparse._ActionsContainer] = {SERVICE: parser}
    for field in fields:
        info = Settings.model_fields[field]
        meta = flag_info(field)
        group = groups.get(meta["group"])
        if group is None:
            group = groups[meta["group"]] = parser.add_argument_group(meta["group"])
        names = [name for name in (meta["short"], flag_name(field)) if name]
        description = (info.description or "").replace("`", "")
        kwargs: dict[str, Any] = {
            "help": f"{description} (env {env_help(field)}; default {shown_default(field)})",
            "metavar": meta["metavar"],
        }
        annotation = info.annotation
        if annotation is bool:
            kwargs |= {"action": "store_true", "default": None}
            del kwargs["metavar"]
        elif choices := _choices(annotation):
            kwargs |= {"choices": choices}
            if all(c.isupper() for c in choices):  # log levels: any case, as the env var
                kwargs["type"] = str.upper
        elif get_origin(annotation) is list:
            if get_args(annotation) == (float,):  # one flag, comma-separated numbers
                kwargs["type"] = lambda text: [float(v) for v in text.split(",")]
            else:
                kwargs["action"] = "append"
        elif annotation in (int, float):
            kwargs["type"] = annotation
        elif annotation == Path | None:
            kwargs["type"] = Path
        group.add_argument(*names, **kwargs)


def _choices(annotation: Any) -> list[str] | None:
    """The values of a Literal (or an optional Literal), else None."""
    for candidate in (annotation, *get_args(annotation)):
        if get_origin(candidate) is Literal:
            return list(get_args(candidate))
    return None


def _add_view_arguments(parser: argparse.ArgumentParser) -> None:
    """What every view of a running service takes: its namespace and the frame shown."""
    add_settings_arguments(parser, ["namespace"])
    parser.add_argument(
        "--base-frame", default="base_link", help="the frame to show (default base_link)"
    )


def _add_robot_arguments(parser: argparse.ArgumentParser) -> None:
    """A simulated ROS4HRI robot in place of a JSON tracker, and its recording."""
    parser.add_argument(
        "--ros2", action="store_true",
        help="a simulated ROS 2 robot running ROS4HRI instead: /tf (the body_<id> and "
        "face_<id> frames in its camera's optical frame), /tf_static, /humans/*/tracked and "
        "the persons linking a face and a body, anonymous ones recognised as known ones",
    )  # fmt: skip
    parser.add_argument(
        "--record", type=Path, metavar="OUT",
        help="with --ros2: also write the robot's topics into a new ROS 2 bag (OUT/, or "
        "OUT/OUT.mcap for OUT.mcap), for facing-service replay and ROS tools",
    )  # fmt: skip


def _add_serving_arguments(parser: argparse.ArgumentParser, port: int, whose: str) -> None:
    """A view that serves (``view``, ``foxglove``): what it reads, where it listens."""
    _add_view_arguments(parser)
    parser.add_argument(
        "--host", type=listen_address, default="127.0.0.1",
        help="address to listen on (default 127.0.0.1: this machine only)",
    )  # fmt: skip
    parser.add_argument(
        "--port", type=port_number, default=port,
        help=f"port to listen on (default {port}{whose}; 0: any free port, said when it starts)",
    )  # fmt: skip
    add_zenoh_arguments(parser)


def _add_scene_arguments(parser: argparse.ArgumentParser) -> None:
    add_settings_arguments(parser, ["namespace"])
    parser.add_argument(
        "--base-frame", default="base_link", help="frame of the poses (default base_link)"
    )
    parser.add_argument(
        "--people",
        type=number(1, strict=False, integer=True),
        default=5,
        help="people in the scene (5)",
    )
    parser.add_argument("--rate-hz", type=POSITIVE, default=30.0, help="poses per second (30)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (0)")


#: The camera's flags' defaults (by destination): a demo of simulated people refuses the
#: flags given otherwise, as it would ignore them.
CAMERA_DEFAULTS: dict[str, object] = {
    "calibration": None, "fov_deg": 65.0, "camera_pose": None, "max_faces": 5, "id_prefix": "f",
    "reach_m": None,
}  # fmt: skip


def _add_camera_arguments(parser: argparse.ArgumentParser) -> None:
    """How the camera front end sees: its intrinsics, its mount, how many faces."""
    parser.set_defaults(**CAMERA_DEFAULTS)
    lens = parser.add_mutually_exclusive_group()
    lens.add_argument(
        "--calibration", type=Path, metavar="FILE",
        help="the camera's intrinsics: a ROS camera_info YAML or an OpenCV calibration file",
    )  # fmt: skip
    lens.add_argument(
        "--fov-deg", type=field_of_view,
        help="without a calibration: the camera's horizontal field of view (default 65, a "
        "laptop's or a USB webcam's; every distance scales with it)",
    )  # fmt: skip
    parser.add_argument(
        "--camera-pose", type=finite, nargs=6, metavar=("X", "Y", "Z", "YAW", "PITCH", "ROLL"),
        help="the camera's pose in --base-frame (metres, degrees; static_transform_publisher's "
        "order); default: at its origin, looking along x (x forward, y left, z up)",
    )  # fmt: skip
    parser.add_argument(
        "--reach-m", type=number(0.5, strict=False, most=20.0), metavar="METRES",
        help="how far faces are looked for (default 5: across a room; 1.5: the whole frame "
        "only, about half the CPU; 8: smaller tiles, a far face found later)",
    )  # fmt: skip
    parser.add_argument(
        "--max-faces", type=number(1, strict=False, integer=True),
        help="faces followed at once (default 5)",
    )  # fmt: skip
    parser.add_argument(
        "--id-prefix", type=id_prefix,
        help="the faces' ids are this and a count (default f: f1, f2, ...); two cameras "
        "publishing to one service need two prefixes",
    )  # fmt: skip


def _add_camera_command(commands: Any) -> None:
    camera = commands.add_parser(
        "camera",
        help="people in front of a camera: their faces' poses as the service's input",
        description="Read frames from a camera, a video or a folder of images, find each face "
        "and its head pose (MediaPipe's face mesh, a generic face fitted with the camera's "
        "intrinsics), keep an id per face and publish each as a pose (the REP 155 face frame: "
        "x out of the face) on NS/bodies/<id>/pose/<base-frame>; a face lost is DELETEd. "
        "Prints a line whenever a face starts or stops facing the camera. An optional extra: "
        "pip install 'facing-service[camera]'.",
    )
    source = camera.add_mutually_exclusive_group()
    source.add_argument("--device", type=number(0, strict=False, integer=True), default=0,
                        help="camera index (default 0: /dev/video0)")  # fmt: skip
    source.add_argument(
        "--video", type=Path, metavar="FILE", help="a video file, played in real time"
    )
    source.add_argument("--images", type=Path, metavar="DIR", help="a folder of images")
    camera.add_argument(
        "--loop", action="store_true", help="start a video or folder over at its end"
    )
    camera.add_argument("--images-fps", type=POSITIVE, default=5.0,
                        help="with --images: images a second (default 5)")  # fmt: skip
    for side, asked in (("width", 640), ("height", 480)):
        camera.add_argument(f"--{side}", type=number(1, strict=False, integer=True),
                            help=f"frame {side} asked of a camera (default {asked}); with "
                            "--images, the frames' (default: the first image's own)")  # fmt: skip
    camera.add_argument(
        "--base-frame", default="base_link",
        help="the frame of the poses (default base_link, as run, watch and view: the camera "
        "at the robot's origin, looking along x, unless --camera-pose places it)",
    )  # fmt: skip
    _add_camera_arguments(camera)
    add_settings_arguments(camera, ["namespace", "threshold_deg", "hysteresis_deg"])
    add_zenoh_arguments(camera)


def build_parser() -> _Parser:
    parser = _Parser(
        prog="facing-service",
        description="Which tracked bodies are oriented toward the robot, over zenoh.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {VERSION}")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    run = commands.add_parser(
        "run",
        help="run the service",
        description="Run the facing service: read poses (or a ROS 2 robot's topics) from "
        "zenoh, publish who faces the robot and their engagement, answer queries. Every flag "
        "can also come from its FACING_* variable; docs/configuration.md lists them.",
    )
    add_settings_arguments(run, Settings.model_fields)

    health = commands.add_parser(
        "health",
        help="exit 0 when a running service answers its status query, 1 otherwise",
        description="Query NS/services/facing/<instance>/status and print one line per "
        "answer (the whole status as JSON with --json). Reads the same FACING_* variables "
        "as 'run' (so a container's health check "
        "needs no flags); it never listens, and connects to the service's listen "
        "endpoints on loopback when no connect endpoint is set.",
    )
    add_settings_arguments(health, ["namespace"])
    health.add_argument(
        "--instance",
        help=f"the instance to check, or '*' for any (env {env_name('instance')}; default *)",
    )
    health.add_argument("--timeout", type=POSITIVE, default=3.0, help="seconds to wait for a "
                        "service to be discovered and answer (default 3)")  # fmt: skip
    health.add_argument("--json", action="store_true",
                        help="print each whole status as JSON, one a line")  # fmt: skip
    health.add_argument("--require-input", action="store_true", help="exit 1 also while the "
                        "service hears no input it can use (silent, or a robot's /tf that "
                        "does not reach --base-frame): a health check that fails while "
                        "nothing works")  # fmt: skip
    health.add_argument(
        "--health-config",
        type=Path,
        metavar="FILE",
        help="zenoh config of the health check's own identity, used instead of --config "
        "and --cfg (env FACING_HEALTH_CONFIG): under access control the service's "
        "identity may not ask for the status",
    )
    add_zenoh_arguments(health)

    router = commands.add_parser(
        "router",
        help="run a zenoh router (access control included) with no zenohd installed",
        description="A zenoh session in router mode with the given config, e.g. "
        "examples/secure/router.json5, until SIGTERM or Ctrl-C. The other commands' session "
        "flags but -m/--mode: the mode is always router.",
    )
    add_settings_arguments(router, ["log_level"])
    # the mode is always router, and a router waits for no router (so its help does not
    # offer --exit-without-router)
    add_settings_arguments(
        router, [f for f in ZENOH_FIELDS if f not in ("mode", "exit_without_router")]
    )

    replay = commands.add_parser(
        "replay",
        help="play a ROS 2 bag (.db3 or .mcap), or a session 'record' kept, onto zenoh",
        description="A ROS 2 bag: its messages go out unchanged at the recorded pace (times "
        "--rate), in rmw_zenoh's format or the bridge's; transient-local topics "
        "(/tf_static...) are served from publication caches, so a service started meanwhile "
        "still gets them. A session kept by 'record' (an MCAP file): its poses and their "
        "DELETEs, into --namespace; with --record, this run is kept likewise.",
    )
    replay.add_argument("bag", type=Path, help="a rosbag2 folder, or its .db3/.mcap file")
    replay.add_argument("--rate", type=POSITIVE, default=1.0, help="speed factor (default 1)")
    replay.add_argument(
        "--record",
        type=Path,
        metavar="OUT",
        help="a ROS 2 bag: write what the service publishes on the robot's topics (run "
        "--output ros2) into a new ROS 2 bag, which is a folder: OUT/ (sqlite3), or for "
        "OUT.mcap the folder OUT/ holding OUT.mcap and its metadata.yaml; a session: keep "
        "this run as a new session file OUT.mcap, as 'record' does",
    )
    add_settings_arguments(
        replay, ["namespace", "ros_format", "ros_distro", "ros_domain_id", "ros_namespace"]
    )
    add_zenoh_arguments(replay)

    record = commands.add_parser(
        "record",
        help="keep a running session as MCAP: poses, results, levels, groups, status",
        description="Subscribe to everything in the namespace (the tracker's poses and all the "
        "service publishes) and write it as it comes into a new MCAP file, each key a topic, "
        "JSON with the contract's JSON Schemas, the status once a second: for the Foxglove app, "
        "and for 'replay OUT.mcap', which plays its poses into a service again. The foxglove "
        "extra: pip install 'facing-service[foxglove]'.",
    )
    record.add_argument("out", type=Path, metavar="OUT.mcap", help="the new file")
    record.add_argument("--duration-s", type=POSITIVE, help="stop after this long")
    add_settings_arguments(record, ["namespace"])
    add_zenoh_arguments(record)

    inspect = commands.add_parser(
        "inspect",
        help="show what a ROS 2 robot publishes on zenoh, and the flags that read it",
        description="Listen for a robot's /tf, /tf_static and /humans/*/tracked in every "
        "format, domain and namespace (as ros2 topic list -v would), then print the topics "
        "with their rate and rmw_zenoh form, the TF tree with its roots (as view_frames), the "
        "tracked ids, and the 'run' flags that read them. Start here when nothing comes out.",
    )
    inspect.add_argument(
        "--seconds", type=POSITIVE, default=3.0, help="how long to listen (default 3)"
    )
    inspect.add_argument(
        "--base-frame",
        default="base_link",
        help="the robot's reference frame the service would use (default base_link)",
    )
    add_zenoh_arguments(inspect)

    simulate = commands.add_parser(
        "simulate",
        help="publish a synthetic scene of people, like a body tracker would",
        description="People walk around the robot, stop, turn toward it and away, appear "
        "and leave (DELETE), with tracker-like jitter on position and yaw. Deterministic "
        "for a given --seed.",
    )
    _add_scene_arguments(simulate)
    simulate.add_argument("--duration-s", type=POSITIVE, help="stop after this long")
    _add_robot_arguments(simulate)
    add_settings_arguments(simulate, ["ros_format", "ros_distro", "ros_domain_id", "ros_namespace"])
    add_zenoh_arguments(simulate)

    watch = commands.add_parser(
        "watch",
        help="live terminal view: a map around the robot and a table",
        description="Follow a running deployment's results: a top-down map around the "
        "robot (R; x up, y left; 1 m rings) with each person as an arrow along their "
        "heading, people facing the robot highlighted and named, and a table of id, facing, "
        "angle, distance and for how long. Redraws 10 times a second; --once prints one "
        "frame; with its output redirected (a file, a pipe), it writes a frame a second.",
    )
    _add_view_arguments(watch)
    watch.add_argument("--once", action="store_true", help="print one frame and exit")
    watch.add_argument(
        "--wait-s", type=NON_NEGATIVE, default=1.0, help="with --once: gather data this long first"
    )
    watch.add_argument("--svg", type=Path, help="also save the last frame as an SVG image")
    add_zenoh_arguments(watch)

    view = commands.add_parser(
        "view",
        help="live page in a browser: a radar of the base frame, a table, groups",
        description="Serve a live page of what a running service decides: a top-down radar "
        "of the base frame (the robot, people with their facing cones coloured by "
        "engagement level, groups, who faces whom), a table beside it and the connection "
        "state, pushed to the browser as it changes. A client of the service's keys like "
        "watch: on a laptop, through a robot's router, in a container. Listens on "
        "127.0.0.1 unless --host says otherwise; nothing is fetched from the internet.",
    )
    _add_serving_arguments(view, 8780, "")

    fox = commands.add_parser(
        "foxglove",
        help="the scene live in the Foxglove app, over Foxglove's WebSocket protocol",
        description="Serve what a running service decides to the Foxglove app (Open "
        "connection, Foxglove WebSocket): people where they stand with their facing cones "
        "coloured by level and labels, groups and their members, who faces whom, where to "
        "join and greet, the robot, in the base frame (/facing/scene), each person's frame "
        "(/facing/tf) and the page's model (/facing/model). A client of the service's keys "
        "like view. The foxglove extra: pip install 'facing-service[foxglove]'.",
    )
    _add_serving_arguments(fox, 8765, ", Foxglove's")

    demo = commands.add_parser(
        "demo",
        help="the service, a simulated scene and the live view, in one process",
        description="Nothing else needed: an embedded service on loopback, a simulator "
        "publishing people into it, and the watch view of the results. Ctrl-C ends it.",
    )
    _add_scene_arguments(demo)
    demo.add_argument("--duration-s", type=POSITIVE, help="end by itself after this long")
    demo.add_argument("--svg", type=Path, help="save the last frame as an SVG image")
    demo.add_argument(
        "--camera", nargs="?", const="0", metavar="SOURCE",
        help="people in front of a camera instead of a simulated scene: a camera index "
        "(default 0), a video file or a folder of images (played in a loop); the camera extra",
    )  # fmt: skip
    _add_camera_arguments(demo)
    _add_robot_arguments(demo)
    add_settings_arguments(demo, ["threshold_deg"])
    demo.add_argument(
        "--view-port", type=port_number, default=8780,
        help="the live page's port on 127.0.0.1, beside the terminal view (default 8780; "
        "0: any free port)",
    )  # fmt: skip

    _add_camera_command(commands)

    export = commands.add_parser(
        "export-schemas",
        help="write the wire contract's JSON Schemas to a folder",
        description="Write the JSON Schemas of every payload of the wire contract (the "
        "models in schemas.py) to DIRECTORY, as committed in schemas/.",
    )
    export.add_argument("directory", type=Path)
    parser.commands = dict(commands.choices)
    return parser
