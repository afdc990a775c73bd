"""``facing-service record OUT.mcap`` and ``facing-service replay SESSION.mcap``: the
commands of a session kept as MCAP (``session_record``, ``session_replay``), with their
refusals in one line each."""

from __future__ import annotations

import argparse
import sys
import threading
import time
from pathlib import Path

import zenoh

from ..config.session import opened, zenoh_config
from ..config.settings import Settings
from ..contract.words import for_how_long
from .record import new_path_refusal
from .session_record import SessionRecorder, missing_extra


def out_refusal(flag: str, out: Path) -> str | None:
    """Why a new session file cannot be written at ``out`` (naming ``flag``), or None."""
    if out.suffix != ".mcap":
        return f"{flag} {str(out)!r}: a session is an .mcap file"
    return new_path_refusal(flag, out, out)


def _session_for(
    command: str, refused: str | None, line: str, settings: Settings
) -> zenoh.Session | int:
    """The session a command runs on once it said ``line``, or its exit code after one
    line saying why not: 2 when refused, 1 when zenoh refuses."""
    if refused:
        print(f"facing-service {command}: {refused}", file=sys.stderr)
        return 2
    print(line, flush=True)
    session = opened(zenoh_config(settings), command)
    return 1 if session is None else session


def record_command(args: argparse.Namespace, settings: Settings, stop: threading.Event) -> int:
    """``record``: until Ctrl-C or ``--duration-s``. Returns the exit code."""
    refused = missing_extra() or out_refusal("OUT.mcap", args.out)
    line = f"recording {settings.namespace}/** to {args.out}{for_how_long(args.duration_s)}"
    session = _session_for("record", refused, line, settings)
    if isinstance(session, int):
        return session
    with session:
        recorder = SessionRecorder(session, settings.namespace, args.out)
        try:
            stop.wait(args.duration_s)
        finally:
            messages, topics = recorder.close()
    print(f"recorded {messages} messages on {topics} topics ({recorder.inputs} poses, "
          f"{recorder.deletes} deletes) to {args.out}")  # fmt: skip
    return 0


def replay_session(args: argparse.Namespace, settings: Settings, stop: threading.Event) -> int:
    """``replay SESSION.mcap``: its poses into ``--namespace``; with ``--record``, this run
    kept too. Returns the exit code."""
    from .session_replay import play

    refused = missing_extra() or (args.record and out_refusal("--record", args.record))
    line = f"replaying the session {args.bag} at {args.rate:g}x into {settings.namespace}"
    session = _session_for("replay", refused, line, settings)
    if isinstance(session, int):
        return session
    with session:
        recorder = (
            SessionRecorder(session, settings.namespace, args.record) if args.record else None
        )
        time.sleep(1.0)  # let a peer or the router see this session before the first pose
        played = play(session, args.bag, settings.namespace, args.rate, stop.is_set)
        if recorder is not None:
            time.sleep(1.0)  # the service's last answers on their way
            messages, topics = recorder.close()
            print(f"recorded {messages} messages on {topics} topics to {args.record}")
    print(f"sent {played.poses} poses and {played.deletes} deletes ({played.duration_s:.1f} s "
          f"recorded) in {played.elapsed_s:.1f} s")  # fmt: skip
    return 0
