"""This package's version, as installed: what the status, ``--version`` and the public
``facing_service.__version__`` say (here, so that the service need not import the public
face to say it)."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

try:
    VERSION = version("facing-service")
except PackageNotFoundError:  # running from a source tree that was never installed
    VERSION = "0.0.0+unknown"
