"""Command line: ``facing-service run`` and ``facing-service export-schemas``.

The zenoh flags are those of zenoh's own example programs, so a zenoh user already knows
them; every ``run`` flag can also come from a ``FACING_<NAME>`` environment variable
(what a container is configured with).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import signal
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from types import FrameType

import zenoh
from pydantic import ValidationError

from . import __version__, keys
from .config import Settings, env_name, load_settings, probe_config
from .schemas import ServiceStatus, json_schemas
from .service import FacingService

log = logging.getLogger("facing_service")


def _default(field: str) -> str:
    value = Settings.model_fields[field].default
    return f"env {env_name(field)}; default {value if value not in (None, []) else 'none'}"


def add_zenoh_arguments(parser: argparse.ArgumentParser) -> None:
    """The session flags every zenoh example program takes."""
    group = parser.add_argument_group("zenoh session")
    group.add_argument(
        "-m",
        "--mode",
        choices=["peer", "client", "router"],
        help=f"zenoh session mode ({_default('mode')}: the config file's, else peer)",
    )
    group.add_argument(
        "-e",
        "--connect",
        action="append",
        metavar="ENDPOINT",
        help=f"endpoint to connect to, repeatable ({_default('connect')}; comma-separated)",
    )
    group.add_argument(
        "-l",
        "--listen",
        action="append",
        metavar="ENDPOINT",
        help=f"endpoint to listen on, repeatable ({_default('listen')}; comma-separated)",
    )
    group.add_argument(
        "-c",
        "--config",
        type=Path,
        metavar="FILE",
        help=f"zenoh JSON5 config file; flags override it ({_default('config')})",
    )
    group.add_argument(
        "--no-multicast-scouting",
        action="store_true",
        default=None,
        help=f"disable multicast scouting ({_default('no_multicast_scouting')})",
    )
    group.add_argument(
        "--cfg",
        action="append",
        metavar="KEY:VALUE",
        help="any zenoh config key with a JSON5 value, repeatable, e.g. "
        "'scouting/delay:0' (env FACING_CFG; ';'-separated)",
    )


def _build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="facing-service",
        description="Which tracked bodies are oriented toward the robot, over zenoh.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", required=True)

    run = commands.add_parser("run", help="run the service")
    run.add_argument("--namespace", help=f"key prefix ({_default('namespace')})")
    run.add_argument(
        "--base-frame",
        help=f"base frame to serve, or '*' for every frame ({_default('base_frame')})",
    )
    run.add_argument(
        "--threshold-deg",
        type=float,
        help=f"half-angle of the facing cone ({_default('threshold_deg')})",
    )
    run.add_argument(
        "--hysteresis-deg",
        type=float,
        help=f"extra angle a facing body may turn before it stops facing "
        f"({_default('hysteresis_deg')})",
    )
    run.add_argument(
        "--stale-after-s",
        type=float,
        help=f"a body with no pose for this long is lost ({_default('stale_after_s')})",
    )
    run.add_argument(
        "--max-payload-bytes",
        type=int,
        help=f"larger pose payloads are rejected ({_default('max_payload_bytes')})",
    )
    run.add_argument(
        "--max-bodies",
        type=int,
        help=f"most bodies tracked over all frames; new ones beyond are rejected "
        f"({_default('max_bodies')})",
    )
    run.add_argument(
        "--instance",
        help=f"this service's name in NS/services/facing/<instance> "
        f"(env {env_name('instance')}; default <host name>-<pid>)",
    )
    run.add_argument("--log-level", help=f"log level ({_default('log_level')})")
    add_zenoh_arguments(run)

    health = commands.add_parser(
        "health",
        help="exit 0 when a running service answers its status query, 1 otherwise",
        description="Query NS/services/facing/<instance>/status and print each answer as "
        "JSON. Reads the same FACING_* variables as 'run' (so a container's health check "
        "needs no flags); it never listens, and connects to the service's listen "
        "endpoints on loopback when no connect endpoint is set.",
    )
    health.add_argument("--namespace", help=f"key prefix ({_default('namespace')})")
    health.add_argument(
        "--instance",
        help=f"the instance to check, or '*' for any (env {env_name('instance')}; default *)",
    )
    health.add_argument(
        "--timeout", type=float, default=3.0, help="seconds to wait for answers (default 3)"
    )
    add_zenoh_arguments(health)

    export = commands.add_parser(
        "export-schemas", help="write the wire contract's JSON Schemas to a folder"
    )
    export.add_argument("directory", type=Path)
    return parser


def _run(args: argparse.Namespace) -> int:
    try:
        settings = load_settings(vars(args), os.environ)
    except ValidationError as error:
        print(f"facing-service: invalid setting: {error}", file=sys.stderr)
        return 2
    logging.basicConfig(
        level=settings.log_level,
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    stop = threading.Event()

    def on_signal(signum: int, _frame: FrameType | None) -> None:
        log.info("received %s, shutting down", signal.Signals(signum).name)
        stop.set()

    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    try:
        service = FacingService(settings).start()
    except zenoh.ZError as error:
        print(f"facing-service: cannot start zenoh: {error}", file=sys.stderr)
        return 1
    try:
        stop.wait()
    finally:
        service.close()
    log.info("stopped")
    return 0


def query_status(
    session: zenoh.Session, namespace: str, instance: str, timeout: float
) -> list[ServiceStatus]:
    """The status of every running service matching ``instance`` (``*`` for all)."""
    selector = keys.status_key(namespace, instance)
    return [
        ServiceStatus.model_validate_json(reply.ok.payload.to_bytes())
        for reply in session.get(selector, timeout=timeout)
        if reply.ok is not None
    ]


def _health(args: argparse.Namespace) -> int:
    instance = args.instance or os.environ.get(env_name("instance")) or "*"
    try:
        settings = load_settings({**vars(args), "instance": None}, os.environ)
        if instance != "*":
            keys.validate_name(instance, "instance")
    except (ValidationError, ValueError) as error:
        print(f"facing-service health: invalid setting: {error}", file=sys.stderr)
        return 2
    try:
        with zenoh.open(probe_config(settings)) as session:
            answers = query_status(session, settings.namespace, instance, args.timeout)
    except zenoh.ZError as error:
        print(f"facing-service health: cannot reach zenoh: {error}", file=sys.stderr)
        return 1
    for status in answers:
        print(status.model_dump_json())
    if not answers:
        selector = keys.status_key(settings.namespace, instance)
        print(f"facing-service health: no answer on {selector}", file=sys.stderr)
    return 0 if any(status.status == "ok" for status in answers) else 1


def _export_schemas(args: argparse.Namespace) -> int:
    args.directory.mkdir(parents=True, exist_ok=True)
    for name, schema in json_schemas().items():
        (args.directory / name).write_text(json.dumps(schema, indent=2) + "\n")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    args = _build_parser().parse_args(argv)
    command = {"run": _run, "health": _health, "export-schemas": _export_schemas}
    return command[args.command](args)
