"""Command line: ``facing-service run`` and ``facing-service export-schemas``.

The zenoh flags are those of zenoh's own example programs, so a zenoh user already knows
them; every ``run`` flag can also come from a ``FACING_<NAME>`` environment variable
(what a container is configured with).
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from types import FrameType
from typing import Any, Literal, NoReturn, get_args, get_origin

import zenoh
from rich.console import Console

from . import __version__
from .client import health
from .client.client import FacingClient
from .client.sim import Scene, TrackerPublisher, simulate
from .client.watch import Watcher, natural_order
from .config.disclosure import zenoh_failure
from .config.settings import (
    SERVICE,
    ZENOH,
    Settings,
    SettingsError,
    env_help,
    env_name,
    flag_info,
    flag_name,
    load_settings,
    shown_default,
    zenoh_config,
)
from .contract import keys
from .contract.schemas import json_schemas
from .ros2.record import replay_refusal
from .shell.service import run_until
from .tools.demo import run_demo
from .tools.router import router_config, serve

log = logging.getLogger("facing_service")

#: Our log levels as zenoh's: one level quieter (its log is verbose), and never its debug
#: or trace, which print the session's whole config, passwords and keys included
#: (zenoh::api::session, measured). RUST_LOG, set by an operator who knows, still wins.
_ZENOH_LEVELS = {
    "DEBUG": "info",
    "INFO": "warn",
    "WARNING": "warn",
    "ERROR": "error",
    "CRITICAL": "error",
}


class _Parser(argparse.ArgumentParser):
    """One line for a bad argument, naming it (argparse would print the whole usage
    first); no abbreviated flags (``--threshold 30`` is not ``--threshold-deg 30``)."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, allow_abbrev=False, **kwargs)  # type: ignore[arg-type]
        self.commands: dict[str, argparse.ArgumentParser] = {}  # the top level's commands

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: {message} (see {self.prog} --help)\n")


def _number(minimum: float, *, strict: bool, integer: bool = False) -> Callable[[str], float]:
    """An argparse type: a finite number above (or from) ``minimum``."""

    def parse(text: str) -> float:
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
        if not math.isfinite(value) or value < minimum or (strict and value == minimum):
            bound = f"> {minimum:g}" if strict else f">= {minimum:g}"
            raise argparse.ArgumentTypeError(f"must be a number {bound}, got {text}")
        return value

    return parse


POSITIVE = _number(0, strict=True)
NON_NEGATIVE = _number(0, strict=False)


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


def _add_scene_arguments(parser: argparse.ArgumentParser) -> None:
    add_settings_arguments(parser, ["namespace"])
    parser.add_argument(
        "--base-frame", default="base_link", help="frame of the poses (default base_link)"
    )
    parser.add_argument(
        "--people",
        type=_number(1, strict=False, integer=True),
        default=5,
        help="people in the scene (5)",
    )
    parser.add_argument("--rate-hz", type=POSITIVE, default=30.0, help="poses per second (30)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (0)")


def build_parser() -> _Parser:
    parser = _Parser(
        prog="facing-service",
        description="Which tracked bodies are oriented toward the robot, over zenoh.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
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
        description="Query NS/services/facing/<instance>/status and print each answer as "
        "JSON. Reads the same FACING_* variables as 'run' (so a container's health check "
        "needs no flags); it never listens, and connects to the service's listen "
        "endpoints on loopback when no connect endpoint is set.",
    )
    add_settings_arguments(health, ["namespace"])
    health.add_argument(
        "--instance",
        help=f"the instance to check, or '*' for any (env {env_name('instance')}; default *)",
    )
    health.add_argument(
        "--timeout",
        type=POSITIVE,
        default=3.0,
        help="seconds to wait for a service to be discovered and answer (default 3)",
    )
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
    add_settings_arguments(router, [f for f in ZENOH_FIELDS if f != "mode"])  # always router

    replay = commands.add_parser(
        "replay",
        help="play a ROS 2 bag (.db3 or .mcap) onto zenoh as the robot published it",
        description="Messages go out unchanged at the recorded pace (times --rate), in "
        "rmw_zenoh's format or the bridge's; transient-local topics (/tf_static...) are "
        "served from publication caches, so a service started meanwhile still gets them.",
    )
    replay.add_argument("bag", type=Path, help="a rosbag2 folder, or its .db3/.mcap file")
    replay.add_argument("--rate", type=POSITIVE, default=1.0, help="speed factor (default 1)")
    replay.add_argument(
        "--record",
        type=Path,
        metavar="OUT",
        help="write what the service publishes on the robot's topics (run --output ros2) "
        "into a new ROS 2 bag, which is a folder: OUT/ (sqlite3), or for OUT.mcap the "
        "folder OUT/ holding OUT.mcap and its metadata.yaml",
    )
    add_settings_arguments(replay, ["ros_format", "ros_distro", "ros_domain_id", "ros_namespace"])
    add_zenoh_arguments(replay)

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
    add_zenoh_arguments(simulate)

    watch = commands.add_parser(
        "watch",
        help="live terminal view: a map around the robot and a table",
        description="Follow a running deployment's results: a top-down map around the "
        "robot (R; x up, y left; 1 m rings) with each person as an arrow along their "
        "heading, people facing the robot highlighted and named, and a table of id, facing, "
        "angle, distance and for how long. Redraws 10 times a second; --once prints one "
        "frame.",
    )
    add_settings_arguments(watch, ["namespace"])
    watch.add_argument(
        "--base-frame", default="base_link", help="the frame to show (default base_link)"
    )
    watch.add_argument("--once", action="store_true", help="print one frame and exit")
    watch.add_argument(
        "--wait-s", type=NON_NEGATIVE, default=1.0, help="with --once: gather data this long first"
    )
    watch.add_argument("--svg", type=Path, help="also save the last frame as an SVG image")
    add_zenoh_arguments(watch)

    demo = commands.add_parser(
        "demo",
        help="the service, a simulated scene and the live view, in one process",
        description="Nothing else needed: an embedded service on loopback, a simulator "
        "publishing people into it, and the watch view of the results. Ctrl-C ends it.",
    )
    _add_scene_arguments(demo)
    demo.add_argument("--duration-s", type=POSITIVE, help="end by itself after this long")
    demo.add_argument("--svg", type=Path, help="save the last frame as an SVG image")

    export = commands.add_parser(
        "export-schemas",
        help="write the wire contract's JSON Schemas to a folder",
        description="Write the JSON Schemas of every payload of the wire contract (the "
        "models in schemas.py) to DIRECTORY, as committed in schemas/.",
    )
    export.add_argument("directory", type=Path)
    parser.commands = dict(commands.choices)
    return parser


def _stop_on_signals() -> threading.Event:
    """An event set by SIGTERM or SIGINT (Ctrl-C): every long-running command ends on it."""
    stop = threading.Event()

    def on_signal(signum: int, _frame: FrameType | None) -> None:
        log.info("received %s, shutting down", signal.Signals(signum).name)
        stop.set()

    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    return stop


def _session_settings(args: argparse.Namespace) -> Settings | None:
    """Settings from the flags and FACING_* variables, with a zenoh config that zenoh
    accepts, or None after printing why not (one line, naming the flag or variable)."""
    try:
        settings = load_settings(vars(args), os.environ)
        zenoh_config(settings)
    except SettingsError as error:
        print(f"facing-service {args.command}: invalid setting: {error}", file=sys.stderr)
        return None
    return settings


def _log_to_stderr(settings: Settings) -> None:
    """Our log, and zenoh's own at the same level (RUST_LOG, when set, still wins)."""
    logging.basicConfig(
        level=settings.log_level,
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    zenoh.init_log_from_env_or(_ZENOH_LEVELS[settings.log_level])


def _run(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    _log_to_stderr(settings)
    return run_until(settings, _stop_on_signals())


def _health(args: argparse.Namespace) -> int:
    return health.check(vars(args), os.environ, args.instance, args.health_config, args.timeout)


def _router(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    _log_to_stderr(settings)
    stop = _stop_on_signals()
    try:
        serve(router_config(settings), stop)
    except zenoh.ZError as error:
        print(zenoh_failure("router", error), file=sys.stderr)
        return 1
    return 0


def _replay(args: argparse.Namespace) -> int:
    refused = replay_refusal(args.bag, args.record)
    if refused:
        print(f"facing-service replay: {refused}", file=sys.stderr)
        return 2
    settings = _session_settings(args)
    if settings is None:
        return 2
    from .tools.replay import replay  # rosbags: only for the commands that read bags

    return replay(settings, args.bag, args.rate, args.record, _stop_on_signals())


def _inspect(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    from .tools.survey import inspect_robot  # rosbags: only for the commands that read CDR

    return inspect_robot(settings, args.seconds, args.base_frame)


def _simulate(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    stop = _stop_on_signals()
    key = keys.pose_key(settings.namespace, "<id>", args.base_frame)
    until = f" for {args.duration_s:g} s" if args.duration_s else " until Ctrl-C"
    print(f"simulating {args.people} people: poses on {key} at {args.rate_hz:g} Hz{until}")
    try:
        session = zenoh.open(zenoh_config(settings))
    except zenoh.ZError as error:
        print(zenoh_failure("simulate", error), file=sys.stderr)
        return 1
    with session:
        publish = TrackerPublisher(session, progress_every_s=5.0, say=_say)
        ticks = simulate(
            publish,
            Scene(people=args.people, seed=args.seed),
            args.base_frame,
            settings.namespace,
            args.rate_hz,
            args.duration_s,
            should_stop=stop.is_set,
        )
    print(f"published {publish.poses} poses and {publish.deletes} deletes in {ticks} ticks")
    return 0


def _say(line: str) -> None:
    print(line, flush=True)


def _watch(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    stop = _stop_on_signals()
    client = FacingClient(
        settings.namespace, args.base_frame, session_config=zenoh_config(settings)
    )
    try:
        client.open()
    except zenoh.ZError as error:
        print(zenoh_failure("watch", error), file=sys.stderr)
        return 1
    watcher = Watcher(client, args.base_frame)
    try:
        if args.once:
            stop.wait(args.wait_s)
            Console().print(watcher.view())
        else:
            watcher.live(lambda: not stop.is_set())
        if args.svg is not None:
            watcher.save_svg(args.svg)
    finally:
        watcher.close()
        client.close()
    return 0


def _demo(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    logging.basicConfig(level=logging.WARNING)
    seen_facing = run_demo(
        settings.model_copy(update={"base_frame": args.base_frame}),
        Scene(people=args.people, seed=args.seed),
        args.rate_hz,
        args.duration_s,
        _stop_on_signals(),
        args.svg,
    )
    people = ", ".join(sorted(seen_facing, key=natural_order)) or "nobody"
    print(f"faced the robot during the demo: {people}")
    return 0


def _export_schemas(args: argparse.Namespace) -> int:
    try:
        args.directory.mkdir(parents=True, exist_ok=True)
        for name, schema in json_schemas().items():
            (args.directory / name).write_text(json.dumps(schema, indent=2) + "\n")
    except OSError as error:
        print(f"facing-service export-schemas: {args.directory}: {error.strerror}", file=sys.stderr)
        return 2
    print(f"wrote {len(json_schemas())} JSON Schemas to {args.directory}")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args, unknown = parser.parse_known_args(argv)
    if unknown:  # said by the command's own parser: its usage, not the top level's
        parser.commands[args.command].error(f"unrecognized arguments: {' '.join(unknown)}")
    command = {
        "run": _run,
        "health": _health,
        "router": _router,
        "replay": _replay,
        "inspect": _inspect,
        "simulate": _simulate,
        "watch": _watch,
        "demo": _demo,
        "export-schemas": _export_schemas,
    }
    return command[args.command](args)
