"""The ``facing-service`` command's entry point, kept light: a Ctrl-C while the command's
modules are still being imported (zenoh, numpy, pydantic: ~0.7 s) ends it quietly, as one
later does, instead of printing a traceback from importlib (issue 59)."""

from __future__ import annotations

import os
import sys
from typing import NoReturn

#: The exit status of a process ended by Ctrl-C (128 + SIGINT), as shells report it.
INTERRUPTED = 130


def entry() -> NoReturn:
    try:
        from .cli import entry as run_command
    except KeyboardInterrupt:
        sys.stderr.flush()
        os._exit(INTERRUPTED)
    run_command()
