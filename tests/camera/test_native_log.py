"""fd 2 filtered while the camera runs (the filter closed the saved descriptor
while its thread could still write, so a file opened next received stderr lines; and a
filter that died left fd 2 a pipe nobody reads, blocking every writer)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

from facing_service.camera import native_log
from facing_service.camera.native_log import without_native_chatter


def run(program: str, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    path = tmp_path / "program.py"
    path.write_text(textwrap.dedent(program))
    return subprocess.run([sys.executable, str(path)], capture_output=True, text=True,
                          timeout=30, cwd=tmp_path)  # fmt: skip


def test_chatter_is_dropped_and_every_other_line_passed(tmp_path: Path):
    done = run(
        """
        import os
        from facing_service.camera.native_log import without_native_chatter
        with without_native_chatter():
            os.write(2, b"W0000 00:00:1.000 123 feedback.cc:12] chatter\\n")
            os.write(2, b"a real error\\n")
            os.write(2, b"INFO: Created TensorFlow Lite XNNPACK delegate for CPU.\\n")
        os.write(2, b"after\\n")
        """,
        tmp_path,
    )
    assert done.stderr == "a real error\nafter\n", done.stderr


def test_a_slow_passer_never_writes_into_a_file_opened_after(tmp_path: Path):
    """The passer held up past the 2 s join: before, its saved fd was closed and reused."""
    done = run(
        f"""
        import os, re, time
        from facing_service.camera import native_log
        class Slow:  # the filter held up longer than the context's 2 s wait
            def match(self, line):
                time.sleep(3)
                return None
        native_log.CHATTER = Slow()
        with native_log.without_native_chatter():
            os.write(2, b"late line\\n")
        with open({str(tmp_path / "next.txt")!r}, "wb") as f:  # may take the freed number
            time.sleep(4)  # the passer writes meanwhile
            f.write(b"mine\\n")
        """,
        tmp_path,
    )
    assert (tmp_path / "next.txt").read_bytes() == b"mine\n"
    assert done.stderr == "late line\n", done.stderr


def test_a_passer_that_fails_gives_fd_2_back(monkeypatch, tmp_path: Path):
    """Before: the filter's death left fd 2 a pipe nobody read: the next writes failed
    (or, with the pipe held open, blocked once it was full)."""

    def broken(line: bytes) -> None:
        raise RuntimeError("a bug in the filter")

    monkeypatch.setattr(native_log, "CHATTER", type("Broken", (), {"match": staticmethod(broken)}))
    seen = tmp_path / "stderr.txt"
    saved = os.dup(2)
    with open(seen, "wb") as stderr:
        os.dup2(stderr.fileno(), 2)  # stderr as the test sees it: a file
        try:
            with without_native_chatter():
                os.write(2, b"first\n")
                for _ in range(2000):  # 200 KB: more than a pipe holds
                    os.write(2, b"x" * 100)
        finally:
            os.dup2(saved, 2)
            os.close(saved)
    said = seen.read_bytes()
    # every byte, none blocked or lost; the order of what the pipe still held against
    # what went around it after fd 2 came back is not kept (CI saw "first" after 100 x)
    assert said.count(b"first\n") == 1 and said.count(b"x") == 200_000 and len(said) == 200_006


def _pass(lines: list[bytes], write, monkeypatch, tmp_path: Path) -> bytes:
    """``_pass_on`` run here over a pipe holding ``lines``, into a file, with ``write``
    as its os.write (fd 2 untouched: its dup2 is recorded, not done)."""
    reader, writer = os.pipe()
    os.write(writer, b"".join(lines))
    os.close(writer)
    out = tmp_path / "passed.txt"
    target = os.open(out, os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
    monkeypatch.setattr(native_log.os, "dup2", lambda fd, to: None)
    monkeypatch.setattr(native_log.os, "write", write)
    native_log._pass_on(reader, target)
    monkeypatch.undo()
    return out.read_bytes()


def test_a_write_that_fails_half_way_passes_the_rest_of_its_line_once(monkeypatch, tmp_path):
    """A defect found by reading: after a partial write failed, the whole line was written
    again (its start twice)."""
    real, calls = os.write, [0]

    def partial_then_fails(fd: int, data: bytes) -> int:
        calls[0] += 1
        if calls[0] == 2:  # the second line: half of it, then a failure
            return real(fd, data[:4])
        if calls[0] == 3:
            raise OSError("a full disk, for a moment")
        return real(fd, data)

    said = _pass([b"one\n", b"two-two\n", b"three\n"], partial_then_fails, monkeypatch, tmp_path)
    assert said == b"one\ntwo-two\nthree\n"


def test_a_read_that_fails_writes_no_line_twice(monkeypatch, tmp_path):
    """A defect found by reading: after the read itself failed, the previous line, already
    written, was written again."""

    class FailsAfterOne:
        """The pipe as a file: one line, then a read that fails; the rest read raw."""

        def __init__(self, reader: int, _mode: str) -> None:
            self._reader = reader

        def __enter__(self) -> FailsAfterOne:
            return self

        def __exit__(self, *_: object) -> None:
            os.close(self._reader)

        def __iter__(self):
            yield os.read(self._reader, 4)  # "one\n"
            raise OSError("a read that fails")

        def read1(self, size: int) -> bytes:
            return os.read(self._reader, size)

    monkeypatch.setattr(native_log.os, "fdopen", FailsAfterOne)
    said = _pass([b"one\n", b"two\n"], os.write, monkeypatch, tmp_path)
    assert said == b"one\ntwo\n"
