"""The flags every example takes, as zenoh's own examples share theirs (``common.py``):
where the service is, which base frame, for how long; and how an example ends on Ctrl-C."""

from __future__ import annotations

import os
import signal

# Ctrl-C while an example's imports still load (zenoh's, numpy's, pydantic's) ends it
# at once and quietly: nothing is open yet, and an exception raised inside a native
# module's import crashed the interpreter as it exited (seen: SIGSEGV). ``run`` then makes
# Ctrl-C a KeyboardInterrupt again, which closes sessions.
signal.signal(signal.SIGINT, lambda *_: os._exit(0))

import _thread  # noqa: E402
import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import threading  # noqa: E402
from collections.abc import Callable  # noqa: E402
from typing import NoReturn  # noqa: E402

import zenoh  # noqa: E402


def arguments(
    doc: str, extra: Callable[[argparse.ArgumentParser], object] | None = None, frame: bool = True
) -> argparse.Namespace:
    """The parsed flags of an example whose docstring is ``doc`` (its first paragraph is
    the ``--help`` description); ``extra`` adds the example's own; ``frame``: it reads one
    base frame."""
    parser = argparse.ArgumentParser(description=" ".join(doc.split("\n\n")[0].split()))
    parser.add_argument(
        "-e", "--connect", action="append", default=[], metavar="ENDPOINT",
        help="the service's (or its router's) endpoint, e.g. tcp/127.0.0.1:7447; repeatable",
    )  # fmt: skip
    if frame:
        parser.add_argument(
            "--base-frame",
            "--frame",
            dest="frame",
            default="base_link",
            help="the base frame (default base_link); --frame is its older name",
        )
    parser.add_argument("--duration-s", type=float, help="stop after this long")
    if extra is not None:
        extra(parser)
    return parser.parse_args()


def session_config(args: argparse.Namespace) -> zenoh.Config:
    """A plain zenoh session reaching the service: the endpoints given (and then no
    multicast scouting, so that only that deployment answers), else zenoh's defaults."""
    config = zenoh.Config()
    if args.connect:
        config.insert_json5("connect/endpoints", json.dumps(args.connect))
        config.insert_json5("scouting/multicast/enabled", "false")
    return config


def say(line: str) -> None:
    """Print ``line`` now, from any thread (a callback's too). When the reader has gone
    (``examples/subscribe.py | head`` once head has its lines), the example ends quietly,
    as on Ctrl-C, instead of a BrokenPipeError traceback from every callback after."""
    try:
        print(line, flush=True)
    except BrokenPipeError:
        _reader_gone()


def _reader_gone() -> None:
    _stdout_to_devnull()
    if threading.current_thread() is threading.main_thread():
        raise KeyboardInterrupt
    _thread.interrupt_main()  # a callback's thread: the main one ends the example


def run(main: Callable[[], int | None]) -> NoReturn:
    """Run an example's ``main`` and exit with its status; Ctrl-C, or a reader that has
    gone, ends it quietly (each ``with`` block has closed its session by then), not with
    a traceback."""
    try:  # a Ctrl-C still pending from the imports is raised by this very switch
        signal.signal(signal.SIGINT, signal.default_int_handler)
        code = main()
    except KeyboardInterrupt:
        code = 0
    except BrokenPipeError:  # a line printed otherwise than by say()
        _stdout_to_devnull()
        code = 0
    sys.exit(code or 0)


def _stdout_to_devnull() -> None:
    """Python's own advice (the signal module's docs): nothing fails again when stdout is
    flushed at exit."""
    os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
