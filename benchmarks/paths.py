"""Where the benchmarks read and write, wherever their module stands: the repository,
the committed results, the team's shared data beside the clone."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
DOCS = ROOT / "docs"
SHARED_DATA = ROOT.parent / "shared" / "data"
