"""The benchmark harness at tiny sizes, so it never rots. No timing assertions (the machine
is shared): the figures are printed and written; what is checked exactly is what does not
depend on speed: every pose sent is received, nothing is superseded, every ratio and
verdict is there."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # processes, recordings or seconds-long scenarios


ROOT = Path(__file__).resolve().parent.parent


def test_quick_benchmark_run_writes_every_figure(tmp_path):
    out = tmp_path / "latest.json"
    proc = subprocess.run(
        [sys.executable, "-m", "benchmarks", "--quick", "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=240,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    report = json.loads(out.read_text())
    runs = [report["service_ros"]]
    for style in ("put", "publishers"):
        measured = report["styles"][style]
        runs += [measured[kind] for kind in ("relay_put", "relay_publishers", "service")]
        assert measured["cheapest"] in ("relay_put", "relay_publishers")
        assert set(measured["ratios"]) >= {"latency_p50", "latency_p99", "burst_throughput"}
        assert report["verdicts"][f"{style}_zero_loss"] is True
        assert report["verdicts"][f"{style}_nothing_superseded"] is True
    for run in runs:
        assert run["latency"]["n"] == 50
        burst, soak = run["burst"], run["soak"]
        assert burst["sent"] > 0 and soak["sent"] > 0
        assert (burst["received"], burst["lost"]) == (burst["sent"], 0), burst  # BLOCK: none lost
        assert soak["received"] == soak["sent"], soak
        assert "zenoh rx" in soak["cpu_by_thread"], soak  # the breakdown reads every thread
    for style in ("put", "publishers"):  # the service's own threads are told apart by name
        for kind, ours in (("relay_put", False), ("relay_publishers", False), ("service", True)):
            groups = set(report["styles"][style][kind]["soak"]["cpu_by_thread"])
            assert ({"facing-worker", "facing-publish"} <= groups) is ours, (style, kind, groups)
    assert {"ros_cpu_per_pose", "ros_burst_throughput"} <= set(report["ros_ratios"])
    assert report["verdicts"]["ros_zero_loss"] is True
    assert [row["n"] for row in report["core"]] == [1, 100, 10_000]
    assert "targets:" in proc.stdout


def test_the_performance_page_shows_latest_json():
    """docs/performance.md's tables are generated from the committed results, never
    copied by hand (python -m benchmarks.report rewrites them)."""
    from benchmarks import report

    page = report.PAGE.read_text()
    assert report.section(page, json.loads(report.RESULTS.read_text())) == page


def test_the_grid_runs_its_cells_and_loses_nothing(tmp_path):
    """benchmarks.grid (issue 36) at --quick sizes: two cells, every target measured,
    every result of the consumed cell arrived."""
    out = tmp_path / "grid.json"
    proc = subprocess.run(
        [sys.executable, "-m", "benchmarks.grid", "--quick", "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=240,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    cells = json.loads(out.read_text())
    assert [(c["mode"], c["style"], c["consumer"]) for c in cells] == [
        ("peer", "put", "none"),
        ("client", "publishers", "results"),
    ]
    for cell in cells:
        assert set(cell["targets"]) == {
            "relay_put", "relay_publishers", "service", "service-declared"
        }  # fmt: skip
        assert all(t["sent"] == 300 for t in cell["targets"].values())
        assert cell["cheapest_relay"] in ("relay_put", "relay_publishers")
    assert all(t["lost"] == 0 for t in cells[1]["targets"].values())
