"""Every results file is written here, with where its figures came from: the version
measured, the machine, the date, the command and its parameters (``provenance``), so a
figure on a page can be traced to a run and rerun."""

from __future__ import annotations

import json
import os
import platform
from collections.abc import Mapping
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path
from typing import Any

from facing_service import __version__

#: Flags that say where a run writes, not what it measured: left out of the parameters.
NOT_PARAMETERS = {"out", "figure"}


def provenance(command: str, parameters: Mapping[str, Any]) -> dict[str, Any]:
    """Where a run's figures come from; ``parameters`` as the command took them (values
    JSON cannot hold are written as text)."""
    return {
        "version": __version__,
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
            "zenoh": metadata.version("eclipse-zenoh"),
        },
        "date": datetime.now(timezone.utc).strftime("%Y-%m-%d"),
        "command": command,
        "parameters": {
            k: v if isinstance(v, (str, int, float, bool, type(None))) else str(v)
            for k, v in parameters.items()
            if k not in NOT_PARAMETERS
        },
    }


def write(path: Path, results: Mapping[str, Any], command: str, parameters: Mapping[str, Any],
          indent: int = 2) -> None:  # fmt: skip
    """``results`` to ``path`` as JSON, its provenance first."""
    path.parent.mkdir(parents=True, exist_ok=True)
    whole = {"provenance": provenance(command, parameters), **results}
    path.write_text(json.dumps(whole, indent=indent) + "\n")


def add(path: Path, key: str, value: Any, command: str, parameters: Mapping[str, Any]) -> None:
    """``value`` put under ``key`` in the results file at ``path``, beside what an earlier
    run wrote there (its provenance stays; this part's is ``<key>_provenance``)."""
    results = json.loads(path.read_text())
    results[key] = value
    results[f"{key}_provenance"] = provenance(command, parameters)
    path.write_text(json.dumps(results, indent=2) + "\n")


def report(lines: list[str], results: Mapping[str, Any], out: Path | None, command: str,
           parameters: Mapping[str, Any]) -> int:  # fmt: skip
    """A benchmark's end: its tables printed, its results written to ``out`` when asked."""
    print("\n".join(lines))
    if out is not None:
        write(out, results, command, parameters)
    return 0
