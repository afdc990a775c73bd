"""The command line's commands: what ``facing-service run``, ``health``, ``router``,
``replay``, ``inspect``, ``simulate``, ``watch``, ``demo`` and ``export-schemas`` do, and
the logging and signals a process needs. Their flags and checks are ``arguments``'.
"""

from __future__ import annotations

import argparse
import difflib
import json
import logging
import os
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from contextlib import AbstractContextManager, nullcontext
from types import FrameType
from typing import TYPE_CHECKING, NoReturn

import zenoh
from rich.console import Console

from .arguments import CAMERA_DEFAULTS, build_parser
from .client import health
from .client.client import FacingClient
from .client.sim import Crowd, TrackerPublisher, simulate
from .client.watch import Watcher
from .config.disclosure import zenoh_failure
from .config.patience import open_patiently
from .config.profiles import robot_wire
from .config.session import waiting_for_router, zenoh_config
from .config.settings import Settings
from .config.sources import load_settings, source_of
from .contract import keys
from .contract.errors import SettingsError
from .contract.schemas import json_schemas
from .shell.run import run_until
from .tools.demo import Feed, run_demo
from .tools.record import replay_refusal
from .tools.router import router_config, serve
from .tools.session_replay import is_session
from .tools.simulate import crowd_of, simulate_command

if TYPE_CHECKING:
    from .tools.ros_robot import RobotFeed

log = logging.getLogger("facing_service")

#: Our log levels as zenoh's: its warnings (coloured, with the Rust source paths of its
#: build) only from --log-level DEBUG, where they help; below it our own one line says
#: what went wrong, and zenoh's errors still show. Never its debug or trace, which print
#: the session's whole config, passwords and keys included (zenoh::api::session,
#: measured). RUST_LOG, set by an operator who knows, still wins.
_ZENOH_LEVELS = {
    "DEBUG": "info",
    "INFO": "error",
    "WARNING": "error",
    "ERROR": "error",
    "CRITICAL": "error",
}


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
        zenoh_config(settings, lambda field: source_of(field, vars(args), os.environ))
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
    return health.check(
        vars(args), os.environ, args.instance, args.health_config, args.timeout, args.json,
        args.require_input,
    )  # fmt: skip


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
    if is_session(args.bag):  # kept by `record`, not a ROS 2 bag
        settings = _session_settings(args)
        if settings is None:
            return 2
        from .tools.session_command import replay_session

        return replay_session(args, settings, _stop_on_signals())
    refused = replay_refusal(args.bag, args.record)
    if refused:
        print(f"facing-service replay: {refused}", file=sys.stderr)
        return 2
    settings = _session_settings(args)
    if settings is None:
        return 2
    from .tools.replay import replay  # rosbags: only for the commands that read bags

    return replay(settings, args.bag, args.rate, args.record, _stop_on_signals())


def _record(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    from .tools.session_command import record_command  # the foxglove extra, when there

    return record_command(args, settings, _stop_on_signals())


def _inspect(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    from .tools.inspect import inspect_robot  # rosbags: only for the commands that read CDR

    return inspect_robot(settings, args.seconds, args.base_frame)


def _simulate(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    return simulate_command(args, settings, _stop_on_signals(), _say)


def _say(line: str) -> None:
    print(line, flush=True)


def _viewer(args: argparse.Namespace, command: str, stop: threading.Event) -> FacingClient | int:
    """The open client a view of ``--base-frame`` reads (``watch``, ``view``), or the
    exit code when the settings or the session are refused (said in one line). A live
    view waits for its router like ``run`` (a robot's processes start in any order);
    ``watch --once`` is one shot and says at once that nothing answers."""
    settings = _session_settings(args)
    if settings is None:
        return 2
    once = getattr(args, "once", False)
    if not once:
        settings = waiting_for_router(settings)
    config = zenoh_config(settings)
    client = FacingClient(settings.namespace, args.base_frame, session_config=config)
    try:  # only the session's opening waits for the router, not the wait for a service
        session = open_patiently(lambda: zenoh.open(config), settings, stop)
    except zenoh.ZError as error:
        print(zenoh_failure(command, error), file=sys.stderr)
        return 1
    if session is None:  # stopped while zenoh.open waits for the router, in native code:
        return 0  # entry() ends the process without waiting for it
    client.open(session, log_absence=not once)
    if once and client.absence is not None:  # one shot: nothing to draw, and say so
        client.close()
        print(f"facing-service {command}: {client.absence}", file=sys.stderr)
        return 1
    return client


def _watch(args: argparse.Namespace) -> int:
    stop = _stop_on_signals()
    client = _viewer(args, "watch", stop)
    if isinstance(client, int):
        return client
    watcher = Watcher(client, args.base_frame)
    watcher.ask_frames()
    try:
        if args.once:
            stop.wait(args.wait_s)
            Console().print(watcher.view())
        else:
            watcher.live(lambda: not stop.is_set())
        if args.svg is not None:
            watcher.save_svg(args.svg)
    finally:
        client.close()
    return 0


def _view(args: argparse.Namespace) -> int:
    from .client.view.live import run_view  # aiohttp: loaded by the command that serves

    return _serve(args, "view", run_view, "the live page is on {} (Ctrl-C ends it)")


def _foxglove(args: argparse.Namespace) -> int:
    from .tools.session_record import missing_extra

    if missing := missing_extra():
        print(f"facing-service foxglove: {missing}", file=sys.stderr)
        return 2
    from .tools.foxglove_live import serve_scene

    return _serve(args, "foxglove", serve_scene,
                  "the scene is served on {}: in the Foxglove app, Open connection → Foxglove "
                  "WebSocket, that URL (Ctrl-C ends it)")  # fmt: skip


def _serve(args: argparse.Namespace, command: str, serve: Callable[..., None], said: str) -> int:
    """A view that serves what a running service says (``view``, ``foxglove``): until
    Ctrl-C, saying where once it listens (``said`` with the address)."""
    stop = _stop_on_signals()
    client = _viewer(args, command, stop)
    if isinstance(client, int):
        return client
    try:
        serve(client, args.base_frame, args.host, args.port, stop, lambda at: _say(said.format(at)))
    except OSError as error:
        print(f"facing-service {command}: --host {args.host} --port {args.port}: "
              f"{error.strerror or error}", file=sys.stderr)  # fmt: skip
        return 1
    finally:
        client.close()
    return 0


def _camera(args: argparse.Namespace) -> int:
    from .camera.extra import missing_extra  # the extra itself only when it is there

    if missing := missing_extra():
        print(f"facing-service camera: {missing}", file=sys.stderr)
        return 2
    settings = _session_settings(args)
    if settings is None:
        return 2
    from .camera.command import run_camera_command

    return run_camera_command(args, settings, _stop_on_signals())


def _demo(args: argparse.Namespace) -> int:
    settings = _session_settings(args)
    if settings is None:
        return 2
    logging.basicConfig(level=logging.WARNING)
    crowd = crowd_of(args)

    def simulated(session: zenoh.Session, should_stop: Callable[[], bool]) -> None:
        simulate(TrackerPublisher(session), crowd, args.base_frame, settings.namespace,
                 args.rate_hz, should_stop=should_stop)  # fmt: skip

    if refused := _demo_refusal(args):
        print(f"facing-service demo: {refused}", file=sys.stderr)
        return 2
    update: dict[str, object] = {"base_frame": args.base_frame}
    if args.ros2:  # the embedded service reads the robot and answers on its topics
        update |= {"input": "ros2", "output": "ros2"}
    robot = _robot_feed(args, settings, crowd) if args.ros2 else None
    with nullcontext() if args.camera is None else _without_native_chatter():
        feed = robot or (simulated if args.camera is None else _camera_feed(args, settings))
        if isinstance(feed, int):
            return feed
        seen_facing = run_demo(settings.model_copy(update=update), feed, args.duration_s,
                               _stop_on_signals(), args.svg, args.view_port)  # fmt: skip
    people = ", ".join(sorted(seen_facing, key=keys.natural_order)) or "nobody"
    print(f"faced the robot during the demo: {people}")
    if robot is not None:
        robot.report()
    return 0


def _demo_refusal(args: argparse.Namespace) -> str | None:
    """Why the demo's flags cannot go together (one line naming them), or None."""
    if args.ros2 and args.camera is not None:
        return "--ros2 or --camera: the people come from one of them"
    if args.camera is None and (strays := _camera_flags_given(args)):
        return f"{' and '.join(strays)} only with --camera: the simulated people have no camera"
    if args.record is not None and not args.ros2:
        return "--record only with --ros2 (a ROS 2 bag holds a robot's topics)"
    from .tools.record import record_refusal  # no rosbags unless a bag is to be written

    return None if args.record is None else record_refusal(args.record)


def _robot_feed(args: argparse.Namespace, settings: Settings, crowd: Crowd) -> RobotFeed:
    """``demo --ros2``'s people: a simulated ROS4HRI robot on the demo's router."""
    from .tools.ros_robot import RobotFeed  # rosbags: for the ROS 2 demo only

    return RobotFeed(robot_wire(settings), crowd, args.base_frame, args.rate_hz, args.record)


def _without_native_chatter() -> AbstractContextManager[None]:
    """The camera's filter of MediaPipe's native lines, loaded only for ``--camera``."""
    from .camera.native_log import without_native_chatter

    return without_native_chatter()


def _camera_flags_given(args: argparse.Namespace) -> list[str]:
    """The camera's flags given to a demo of simulated people, which would ignore them."""
    return [f"--{name.replace('_', '-')}" for name, default in CAMERA_DEFAULTS.items()
            if getattr(args, name) != default]  # fmt: skip


def _camera_feed(args: argparse.Namespace, settings: Settings) -> Feed | int:
    """``demo --camera``'s feed, or the exit code after one line saying why there is none
    (no extra, no such camera or file, a bad calibration): the camera was asked for, so a
    typo is said and ends the demo rather than showing other people."""
    from .camera.extra import missing_extra

    if missing := missing_extra():
        print(f"facing-service demo: --camera: {missing}", file=sys.stderr)
        return 2
    from .camera.command import demo_source, open_feed, options_of
    from .camera.frames import SourceError

    try:
        source = demo_source(args.camera)
    except SourceError as error:
        print(f"facing-service demo: --camera {args.camera}: {error}", file=sys.stderr)
        return 2
    feed = open_feed(options_of(args, settings, source), "demo")
    if isinstance(feed, int):
        return feed
    print(f"demo: the people are the faces of {source.describe()}", flush=True)

    def faces(session: zenoh.Session, should_stop: Callable[[], bool]) -> None:
        feed.run(TrackerPublisher(session), should_stop, lambda line: None)  # the view says who

    return faces


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


def _with_suggestions(unknown: Sequence[str], flags: Sequence[str]) -> str:
    """The words a command did not take, each misspelt flag with the nearest it takes (as
    a misspelt FACING_ variable gets one) after the values that followed it (``--threshold
    30 (did you mean --threshold-deg?)``, not before the 30)."""
    said: list[str] = []
    hint = ""
    for word in unknown:
        if word.startswith("-"):  # a flag: the previous one's words end here
            said[-1:] = [said[-1] + hint] if said else []
            near = difflib.get_close_matches(word.split("=")[0], flags, n=1)
            hint = f" (did you mean {near[0]}?)" if near else ""
        said.append(word)
    said[-1:] = [said[-1] + hint] if said else []
    return " ".join(said)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args, unknown = parser.parse_known_args(argv)
    if unknown:  # said by the command's own parser: its usage, not the top level's
        command_parser = parser.commands[args.command]
        flags = [o for action in command_parser._actions for o in action.option_strings]
        command_parser.error(f"unrecognized arguments: {_with_suggestions(unknown, flags)}")
    command = {
        "run": _run,
        "health": _health,
        "router": _router,
        "replay": _replay,
        "record": _record,
        "inspect": _inspect,
        "simulate": _simulate,
        "watch": _watch,
        "view": _view,
        "foxglove": _foxglove,
        "demo": _demo,
        "camera": _camera,
        "export-schemas": _export_schemas,
    }
    return command[args.command](args)


def entry() -> NoReturn:
    """The ``facing-service`` command and ``python -m facing_service``: ``main``, then the
    process ends at once. Every session is closed by then; what is left are zenoh's own
    native threads, which may still call into Python while the interpreter finalises, and a
    thread that does aborts the whole process ("FATAL: exception not rethrown", seen 1 time
    in 4 when a viewer had waited for its router). Output is flushed first."""
    try:
        code = main()
    except KeyboardInterrupt:  # before a command set its own handlers: end quietly, as
        code = 128 + signal.SIGINT  # shells report Ctrl-C
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
