"""A FacingClient never keeps a program alive, and closes from anywhere.

Each program runs as a subprocess with a deadline, against a real service over loopback:
it must exit by itself however its own code ends.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

from facing_service import FacingClient
from facing_service.testing import loopback_config

from loopback import send, send_delete, wait_until_answered
from poses import pose_json

#: The program's start, as docs/client.md shows it first: open(), never closed.
OPENED = """\
import sys, time
from facing_service import FacingClient, FacingError
from facing_service.testing import loopback_config
hri = FacingClient(frame="cam", session_config=loopback_config(connect=[{ep!r}]))
hri.open()
hri.on_change(lambda state: None)
print("open", sorted(hri.bodies()), flush=True)
"""

ENDINGS = {
    "ends": "",
    "raises its own error": "raise RuntimeError('the program failed')\n",
    "raises the client's error": "raise FacingError('the client failed')\n",
    "calls sys.exit": "sys.exit(3)\n",
}


def run_program(path: Path, *, interrupt: bool = False) -> tuple[int, str, str]:
    """Run ``path``; ``interrupt``: Ctrl-C once it printed its first line. The program
    must end within 20 s by itself (a hang is killed and fails the test)."""
    proc = subprocess.Popen(
        [sys.executable, str(path)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        assert proc.stdout is not None
        first = proc.stdout.readline()
        if interrupt:
            time.sleep(0.3)  # in the user's loop
            proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        pytest.fail(f"the program never exited; stderr: {err[-2000:]}")
    return proc.returncode, first + out, err


@pytest.fixture
def served(net):
    _, ep = net.service()
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/facing/cam")
    send(tracker, "hri/bodies/a/pose/cam", pose_json("a", "cam", off_deg=5.0, sec=1))
    wait_until_answered(tracker, "hri/bodies/a/facing/cam")
    return ep, tracker


@pytest.mark.parametrize("ending", sorted(ENDINGS))
def test_a_program_that_never_closes_its_client_exits(served, tmp_path, ending):
    """Before: the program printed its traceback (or nothing) and hung for ever, zenoh's
    callback threads keeping the interpreter up."""
    ep, _ = served
    program = tmp_path / "never_closed.py"
    program.write_text(OPENED.format(ep=ep) + ENDINGS[ending])
    code, out, err = run_program(program)
    assert out.startswith("open ['a']"), (out, err)
    expected = {"ends": 0, "calls sys.exit": 3}.get(ending, 1)
    assert code == expected, err


def test_ctrl_c_in_the_programs_own_loop_ends_it(served, tmp_path):
    """Before: the KeyboardInterrupt's traceback, then a hang until a second Ctrl-C."""
    ep, _ = served
    program = tmp_path / "looping.py"
    program.write_text(OPENED.format(ep=ep) + "while True:\n    time.sleep(0.1)\n")
    code, out, err = run_program(program, interrupt=True)
    assert out.startswith("open ['a']")
    assert "KeyboardInterrupt" in err and "Exception ignored" not in err, err
    assert code != 0


def test_a_callback_may_close_its_own_client(served, caplog):
    """Before: close() from on_lost joined the dispatcher from itself ("cannot join
    current thread", swallowed) and left the session open."""
    ep, tracker = served
    closed = threading.Event()
    client = FacingClient(frame="cam", session_config=loopback_config(connect=[ep])).open()

    def close_on_lost(_body: object) -> None:
        client.close()
        closed.set()

    try:
        client.on_lost(close_on_lost)
        send_delete(tracker, "hri/bodies/a/pose/cam")
        assert closed.wait(5)
        assert client._session is None  # the session is closed, not left open
        with pytest.raises(Exception, match="not open"):
            client.bodies()
    finally:
        client.close()  # a second close is harmless
    assert not [r for r in caplog.records if "raised" in r.getMessage()], caplog.text


def test_open_seeds_the_cache_once(served):
    """Before: the liveliness token's history asked for a re-seed while open() seeded
    too: two rounds of queries on two threads for one service."""
    ep, _ = served
    seeds: list[str] = []
    client = FacingClient(frame="cam", session_config=loopback_config(connect=[ep]))
    reseed = client._reseed

    def counted() -> None:
        seeds.append(threading.current_thread().name)
        reseed()

    client._reseed = counted  # type: ignore[method-assign]
    with client:
        time.sleep(0.5)  # the token's history has long arrived
        assert sorted(client.bodies()) == ["a"]
    assert len(seeds) == 1, seeds


def test_the_client_starts_no_thread_that_outlives_the_program(served):
    """What keeps an interpreter up is a non-daemon thread: the client starts none."""
    ep, _ = served
    before = set(threading.enumerate())
    with FacingClient(frame="cam", session_config=loopback_config(connect=[ep])):
        started = [t for t in threading.enumerate() if t not in before]
        assert started and not [t.name for t in started if not t.daemon]
    deadline = time.monotonic() + 5
    while [t for t in started if t.is_alive()]:
        assert time.monotonic() < deadline, [t.name for t in started if t.is_alive()]
        time.sleep(0.02)


def test_the_examples_shape_still_exits(served, tmp_path):
    """The `with` form docs/client.md shows second, unchanged."""
    ep, _ = served
    program = tmp_path / "with_form.py"
    program.write_text(
        textwrap.dedent(f"""\
        from facing_service import FacingClient
        from facing_service.testing import loopback_config
        with FacingClient(frame="cam", session_config=loopback_config(connect=[{ep!r}])) as h:
            print("open", sorted(h.bodies()), flush=True)
        """)
    )
    code, out, err = run_program(program)
    assert (code, out) == (0, "open ['a']\n"), err


def test_at_exit_a_client_is_closed_before_its_inbox(served):
    """Before: the client was registered before its inbox, so exit closed the inbox
    first (the comment said the opposite)."""
    from facing_service.client import inbox

    ep, _ = served
    with FacingClient(frame="cam", session_config=loopback_config(connect=[ep])) as client:
        order = sorted(inbox._OPEN.items(), key=lambda kv: -kv[1])
        mine = [thing for thing, _ in order if thing in (client, client._inbox)]
        assert mine == [client, client._inbox]


def test_a_seed_cut_short_by_close_says_nothing(served, caplog):
    """Before: closing a client while it seeded logged "could not query the service"."""
    ep, _ = served
    client = FacingClient(frame="cam", session_config=loopback_config(connect=[ep]))
    with client:
        pass
    client._reseed()  # what the dispatcher was running when close() came
    assert not [r for r in caplog.records if "could not query" in r.getMessage()]
