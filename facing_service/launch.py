"""The ``facing-service`` command's entry point, kept light: a Ctrl-C while the command's
modules are still being imported (zenoh, numpy, pydantic: ~0.7 s) ends it quietly, as one
later does, instead of printing a traceback from importlib."""

from __future__ import annotations

import os
import signal
import sys
from typing import NoReturn


def entry() -> NoReturn:
    try:
        from .cli import entry as run_command
    except KeyboardInterrupt:  # ended as shells report Ctrl-C: 128 + SIGINT
        sys.stderr.flush()
        os._exit(128 + signal.SIGINT)
    run_command()
