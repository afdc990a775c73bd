"""Whether the camera extra can run here, said before anything imports it: the extra's
install command when it is missing, and the Pythons its wheels exist for."""

from __future__ import annotations

import importlib.util
import sys

#: As the README and docs/camera.md install it: in a venv of its own, from the clone.
INSTALL = "python3 -m venv .venv-camera && .venv-camera/bin/pip install '.[camera]'"
#: mediapipe 0.10.18-0.10.21 publish wheels for CPython 3.9-3.12 only; the package needs
#: 3.10 or later.
PYTHONS = ((3, 10), (3, 12))


def missing_extra() -> str | None:
    """One line saying why the camera front end cannot run here, or None when it can."""
    here = sys.version_info[:2]
    low, high = PYTHONS
    if not low <= here <= high:
        return (
            f"the camera front end needs Python {low[0]}.{low[1]}-{high[0]}.{high[1]} (mediapipe "
            f"0.10.21 has no wheel for Python {here[0]}.{here[1]}); use a venv of one of those"
        )
    if importlib.util.find_spec("mediapipe") is None or importlib.util.find_spec("cv2") is None:
        return f"the camera front end is an optional extra, not installed: {INSTALL}"
    return None
