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
    """Two cells of the grid (a peer put tracker nobody consumes; a client tracker of
    declared publishers consuming the results), every target measured in each, every
    result of the consumed cell arrived; the ROS 2 path and the core."""
    out = tmp_path / "latest.json"
    proc = subprocess.run(
        [sys.executable, "-m", "benchmarks", "--quick", "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    report = json.loads(out.read_text())
    cells = report["grid"]
    assert [(c["mode"], c["style"], c["consumer"]) for c in cells] == [
        ("peer", "put", "none"),
        ("client", "publishers", "results"),
    ]
    targets = {"relay_put", "relay_publishers", "relay_keys", "service"}
    for cell in cells:
        assert set(cell["targets"]) == targets
        assert cell["cheapest_relay"] in targets - {"service"}
        assert set(cell["ratios"]) == {
            "soak_cpu", "soak_cpu_after_flood", "latency_p50", "burst_throughput"
        }  # fmt: skip
        for run in cell["targets"].values():
            assert run["soak"]["sent"] == run["soak_after"]["sent"] == 20 * 30
            assert run["burst"]["sent"] == 2000
    silent, consumed = cells
    for run in silent["targets"].values():  # nobody consumes: CPU only, nothing to count
        assert "latency" not in run and run["burst"]["received"] is None
        assert run["burst"]["drained_s"] > 0
    assert silent["ratios"]["latency_p50"] is None
    for run in (*consumed["targets"].values(), report["service_ros"]):
        assert run["latency"]["n"] == 50
        burst = run["burst"]
        assert (burst["received"], burst["lost"]) == (burst["sent"], 0), burst  # BLOCK
        for soak in (run["soak"], run["soak_after"]):
            assert soak["received"] == soak["sent"], soak
            assert "zenoh rx" in soak["cpu_by_thread"], soak  # every thread is read
    for cell in cells:  # the service's own threads are told apart by name
        for name, run in cell["targets"].items():
            groups = set(run["soak"]["cpu_by_thread"])
            assert ({"facing-worker", "facing-publish"} <= groups) is (name == "service")
    assert report["verdicts"]["zero_loss"] is True
    assert report["verdicts"]["nothing_superseded"] is True
    assert {"ros_cpu_per_pose", "ros_burst_throughput"} <= set(report["ros_ratios"])
    assert report["verdicts"]["ros_zero_loss"] is True
    assert [row["n"] for row in report["core"]] == [1, 100, 10_000]
    assert "targets:" in proc.stdout and "| client | publishers | results |" in proc.stdout


def test_the_performance_page_shows_latest_json():
    """docs/performance.md's tables are generated from the committed results, never
    copied by hand (python -m benchmarks.perf.report rewrites them)."""
    from benchmarks.perf import report

    page = report.PAGE.read_text()
    assert report.section(page, json.loads(report.RESULTS.read_text())) == page


def test_the_churn_benchmark_runs_and_says_every_outage(tmp_path):
    """benchmarks.perf.churn, shortened: two router restarts in 24 s; both said, lost and back;
    nothing lost outside them; the figure drawn (so the hour-long run never rots)."""
    out, figure = tmp_path / "churn.json", tmp_path / "churn.svg"
    proc = subprocess.run(
        [sys.executable, "-m", "benchmarks.perf.churn", "--minutes", "0.4", "--people", "5",
         "--restart-every-s", "8", "--out", str(out), "--figure", str(figure)],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
    result = json.loads(out.read_text())
    assert result["restarts"] == 2
    assert result["outages_said"]["lost"] == result["outages_said"]["back"] == 2
    assert result["accepted"] >= result["sent_outside_outages"] > 0
    assert result["consumer"]["out_of_order"] == 0
    assert figure.read_text().startswith("<svg") and "<polyline" in figure.read_text()


def test_nothing_measured_is_no_target_met():
    """A defect found: the verdicts were ``all()`` over lists that may be empty, so a
    report that measured nothing met every target."""
    from benchmarks.perf.report import TARGETS, verdicts

    run = {"burst": {"lost": 0}, "soak": {"sent": 1, "received": 1},
           "soak_after": {"sent": 1, "received": 1}}  # fmt: skip
    report = {"grid": [], "core": [], "service_ros": run,
              "ros_ratios": {"ros_cpu_per_pose": 1.0, "ros_burst_throughput": 1.0}}  # fmt: skip
    met = verdicts(report)
    assert not any(met[name] for name in TARGETS), met
    assert not met["zero_loss"] and not met["nothing_superseded"] and not met["core_speedup"]
    assert met["ros_zero_loss"]  # measured: one run, nothing lost


def test_every_generated_page_is_its_results_files():
    """One command checks every measured section of the docs."""
    from benchmarks import pages

    assert pages.main(["--check"]) == 0, "regenerate: python -m benchmarks.pages"


def test_the_people_benchmark_streams_the_robots_it_says():
    """benchmarks.perf.people: bodies alone are bodies; persons with a face and a
    body are one participant each, every message of theirs measured."""
    from benchmarks.perf.people import per_message_us, robot

    bodies, messages = robot(3, persons=False)
    assert bodies.subjects() == ["body_b0", "body_b1", "body_b2"] and len(messages) == 3 * 30
    persons, messages = robot(3, persons=True)
    assert persons.subjects() == ["person_p0", "person_p1", "person_p2"]
    assert len(messages) == 2 * 3 * 30  # each face and each body, 30 times a second
    assert per_message_us(2, True, 1.0) > 0


def test_the_participants_benchmark_calls_one_head_said_twice_a_self_group():
    """benchmarks.engagement.participants: a group of two members at one place
    is one human said twice; two people a conversation apart are not."""
    from benchmarks.engagement.participants import self_grouped
    from facing_service.contract.poses import Stamp
    from facing_service.contract.schemas import FacingState, GroupState, Point

    def at(body: str, x: float) -> FacingState:
        return FacingState(
            body_id=body, frame_id="camera_link", stamp=Stamp(sec=1, nanosec=0), facing=True,
            angle_deg=3.0, distance_m=x, robot_in_body=Point(x=x, y=0.0, z=0.0),
            threshold_deg=20.0, position=Point(x=x, y=0.0, z=1.5), heading_deg=180.0,
        )  # fmt: skip

    states = {"person_a": at("person_a", 1.0), "face_a": at("face_a", 1.05),
              "person_b": at("person_b", 2.2)}  # fmt: skip
    group = GroupState.model_validate(
        {"id": "1", "members": ["person_a", "face_a"], "robot": False, "centre": {"x": 1, "y": 0}}
    )
    apart = group.model_copy(update={"members": ["person_a", "person_b"]})
    assert self_grouped(group, states) and not self_grouped(apart, states)
