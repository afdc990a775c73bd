"""Threads named for the OS: what ``top -H`` and the benchmarks' per-thread CPU read."""

from __future__ import annotations

import sys
import threading
from pathlib import Path

import pytest

from facing_service.shell.threads import OS_NAME_MAX, daemon_thread


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc is Linux's")
@pytest.mark.parametrize(
    ("name", "seen"), [("facing-worker", "facing-worker"), ("x" * 20, "x" * OS_NAME_MAX)]
)
def test_the_os_sees_the_threads_name(name: str, seen: str) -> None:
    comm: list[str] = []

    def record() -> None:
        comm.append(Path(f"/proc/self/task/{threading.get_native_id()}/comm").read_text().strip())

    thread = daemon_thread(record, name)
    assert thread.daemon and thread.name == name
    thread.start()
    thread.join(timeout=5)
    assert comm == [seen]
