"""The version the status, --version and ``facing_service.__version__`` say is the
installed distribution's."""

from __future__ import annotations

from importlib.metadata import version

import facing_service
from facing_service.config.version import VERSION


def test_the_version_is_the_installed_distributions():
    assert VERSION == version("facing-service") == facing_service.__version__
