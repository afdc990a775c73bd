"""Daemon threads named for the operating system too, so ``top -H``, ``ps -L`` and the
benchmarks' per-thread CPU (/proc/<pid>/task/<tid>/comm) tell the worker from the
publisher and from zenoh's own threads (Python before 3.14 names only its own object)."""

from __future__ import annotations

import ctypes
import ctypes.util
import sys
import threading
from collections.abc import Callable
from functools import cache

#: Linux's limit on a thread's name, without the terminating NUL.
OS_NAME_MAX = 15
_PR_SET_NAME = 15


@cache
def _prctl() -> Callable[..., int] | None:
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL(ctypes.util.find_library("c"), use_errno=True).prctl
    except (OSError, AttributeError):
        return None


def name_this_thread(name: str) -> None:
    """Give the calling thread ``name`` (cut to 15 bytes) where the OS allows; elsewhere
    nothing (a name is a convenience, never a reason to fail)."""
    if (prctl := _prctl()) is not None:
        prctl(_PR_SET_NAME, name.encode()[:OS_NAME_MAX], 0, 0, 0)


def daemon_thread(target: Callable[[], object], name: str) -> threading.Thread:
    """A daemon thread (not started) that runs ``target`` under ``name``, for Python and
    for the OS."""

    def run() -> None:
        name_this_thread(name)
        target()

    return threading.Thread(target=run, name=name, daemon=True)
