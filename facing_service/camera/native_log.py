"""MediaPipe's native start-up chatter kept off the terminal: its C++ logs INFO and WARNING
lines ("W0000 … Feedback manager requires a model with a single signature …", TF Lite's
"Created … delegate") straight to file descriptor 2, where no Python setting reaches (absl
reads no environment variable). While the front end runs, fd 2 goes through a pipe that
drops those lines and passes everything else, our own lines and its errors included.
"""

from __future__ import annotations

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
    """Within: fd 2 filtered; after: fd 2 as it was, every line passed on written."""
    saved = os.dup(2)
    reader, writer = os.pipe()
    os.dup2(writer, 2)
    os.close(writer)
    passer = threading.Thread(target=_pass_on, args=(reader, saved), daemon=True)
    passer.start()
    try:
        yield
    finally:
        os.dup2(saved, 2)  # the pipe's last writer gone: the passer reads to its end
        passer.join(timeout=2.0)
        os.close(saved)


def _pass_on(reader: int, target: int) -> None:
    with os.fdopen(reader, "rb") as lines:
        for line in lines:
            if not CHATTER.match(line):
                os.write(target, line)
