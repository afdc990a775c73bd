"""MediaPipe's native start-up chatter kept off the terminal: its C++ logs INFO and WARNING
lines ("W0000 … Feedback manager requires a model with a single signature …", TF Lite's
"Created … delegate") straight to file descriptor 2, where no Python setting reaches (absl
reads no environment variable). While the front end runs, fd 2 goes through a pipe that
drops those lines and passes everything else, our own lines and its errors included.

The thread that passes lines on writes to a descriptor of its own, closed by itself when
the pipe ends: one it still writes to is never closed under it and reused by a file opened
next. Should it fail, it puts fd 2 back as it was and passes the rest through
as it is, so a writer to fd 2 never blocks on a pipe nobody reads.
"""

from __future__ import annotations

import contextlib
import os
import re
import threading
from collections.abc import Iterator
from contextlib import contextmanager

#: absl/glog's INFO and WARNING lines, and the two lines TF Lite and absl print unprefixed.
CHATTER = re.compile(
    rb"^([IW]\d{4} [\d:.]+\s+\d+ \S+:\d+\]|INFO: Created TensorFlow Lite"
    rb"|WARNING: All log messages before absl::InitializeLog)"
)


@contextmanager
def without_native_chatter() -> Iterator[None]:
    """Within: fd 2 filtered; after: fd 2 as it was, every line passed on written (within
    2 s: a line still in the pipe after that is written when the thread gets to it)."""
    saved = os.dup(2)
    reader, writer = os.pipe()
    os.dup2(writer, 2)
    os.close(writer)
    passer = threading.Thread(
        target=_pass_on, args=(reader, os.dup(saved)), name="facing-stderr", daemon=True
    )
    passer.start()
    try:
        yield
    finally:
        os.dup2(saved, 2)  # the pipe's last writer gone: the passer reads to its end
        os.close(saved)  # ours only: the passer writes to its own copy
        passer.join(timeout=2.0)


def _pass_on(reader: int, target: int) -> None:
    """Each line read from ``reader`` but the chatter, to ``target``; both closed at the
    end. On a failure, fd 2 is ``target`` again and the rest is passed as it comes: the
    unwritten part of the line at hand first, once (a whole line after a
    partial write said its start twice, and the last line again after a failed read)."""
    owed = b""  # read and to be passed, not yet written
    try:
        with os.fdopen(reader, "rb") as pipe:
            try:
                for line in pipe:
                    owed = line
                    if CHATTER.match(line):
                        owed = b""
                    while owed:
                        owed = owed[os.write(target, owed) :]
            except Exception:
                with contextlib.suppress(OSError):  # nowhere left to say it
                    _write_all(target, owed)  # this line's rest, then fd 2 around the pipe
                    os.dup2(target, 2)
                    while rest := pipe.read1(65536):  # and what the pipe still holds
                        _write_all(target, rest)
    finally:
        os.close(target)


def _write_all(fd: int, data: bytes) -> None:
    while data:
        data = data[os.write(fd, data) :]
