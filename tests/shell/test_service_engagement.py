"""Engagement levels end to end over zenoh: states, events, queries, client callbacks."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from pathlib import Path

from facing_service import FacingClient
from facing_service.testing import loopback_config

from loopback import get, send_delete, wait_until_answered
from poses import replay

ROOT = Path(__file__).resolve().parents[2]


def test_levels_events_queries_and_callbacks(net):
    service, ep = net.service()
    tracker = net.client(ep)
    events = net.recorder(tracker, "hri/events/engagement/cam")
    states = net.recorder(tracker, "hri/bodies/*/engagement/cam")
    wait_until_answered(tracker, "hri/facing/cam")
    engaged, disengaged = [], []
    done = threading.Event()
    with FacingClient(session_config=loopback_config(connect=[ep])) as client:
        client.on_engaged(engaged.append)
        client.on_disengaged(lambda event: (disengaged.append(event), done.set()))

        replay(tracker, "ann", [90.0] * 30 + [0.0] * 45)  # away 1 s, then faces 1.5 s
        (engaged_event,) = events.wait_for(lambda i: i.value["level"] == "ENGAGED")
        (state,) = get(tracker, "hri/bodies/ann/engagement/cam")
        assert state[1]["level"] == "ENGAGED" and state[1]["level_value"] == 3
        assert state[1]["zone"] == "social" and state[1]["score"] > 0.9
        replay(tracker, "ann", [90.0] * 60, start_s=102.5)  # turns away for 2 s
        events.wait_for(
            lambda i: i.value["level"] == "DISENGAGED" and i.value["previous"] == "DISENGAGING"
        )
        assert done.wait(5)

    levels = [(e.value["previous"], e.value["level"]) for e in events.items]
    assert levels == [
        ("UNKNOWN", "DISENGAGED"),
        ("DISENGAGED", "ENGAGING"),
        ("ENGAGING", "ENGAGED"),
        ("ENGAGED", "DISENGAGING"),
        ("DISENGAGING", "DISENGAGED"),
    ]
    # ENGAGED within a second of facing (stamps: facing from t = 101.0)
    engaged_at = engaged_event.value["stamp"]["sec"] + engaged_event.value["stamp"]["nanosec"] / 1e9
    assert 101.0 < engaged_at <= 102.0
    assert [e.body_id for e in engaged] == ["ann"] and [e.body_id for e in disengaged] == ["ann"]
    # states are published on changes, and at most once a second otherwise
    assert 5 <= len([s for s in states.items if s.kind == "put"]) <= 5 + 5

    send_delete(tracker, "hri/bodies/ann/pose/cam")  # lost: the key goes, a last event
    states.wait_for(lambda i: i.kind == "delete")
    lost = events.wait_for(lambda i: i.value["level"] == "UNKNOWN")
    assert lost[0].value["previous"] == "DISENGAGED"
    assert service.status().counters["events_published"] == 6


def test_engagement_flags_reach_the_service(net):
    # 1.5 m away: "social" by default, "public" once the social zone ends at 1.4 m
    _, ep = net.service(engage_above=0.9, disengage_below=0.1, zones_m=[0.3, 1.0, 1.4])
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/facing/cam")
    replay(tracker, "ben", [30.0] * 60)  # score 0.6: enough by default, not with 0.9
    time.sleep(0.5)
    (state,) = get(tracker, "hri/bodies/ben/engagement/cam")
    assert state[1]["level"] == "DISENGAGED" and state[1]["zone"] == "public"


def test_evaluation_runs_at_small_size(tmp_path):
    out = tmp_path / "engagement.json"
    proc = subprocess.run(
        [sys.executable, "-m", "benchmarks.engagement.simulated", "--quick", "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    report = json.loads(out.read_text())
    assert set(report) >= {"ours", "reference", "targets_met"}
    # a simulation on its own clock: deterministic, so these are results, not timings
    assert report["ours"]["to_engaged_s"] < report["reference"]["to_engaged_s"]
    assert all(report["targets_met"].values()), proc.stdout


def test_hri_engagements_rule_as_a_mode_levels_as_robots_run_them(net):
    """`--engagement rule` is hri_engagement 2.0.1's rule on the JSON path (the
    ROS 2 path: test_benchmarks_crossval): no level until half its 10 s window has votes,
    then DISENGAGED, ENGAGING, and ENGAGED only once three quarters of the window voted
    engaged; our levels, events and keys."""
    _, ep = net.service(engagement="rule")
    tracker = net.client(ep)
    events = net.recorder(tracker, "hri/events/engagement/cam")
    wait_until_answered(tracker, "hri/facing/cam")
    replay(tracker, "ann", [90.0] * 180 + [0.0] * 450)  # away 6 s, then faces 15 s
    engaged = events.wait_for(lambda i: i.value["level"] == "ENGAGED", timeout=10)[0]
    levels = [(e.value["previous"], e.value["level"]) for e in events.items]
    assert levels == [
        ("UNKNOWN", "DISENGAGED"),
        ("DISENGAGED", "ENGAGING"),
        ("ENGAGING", "ENGAGED"),
    ], levels
    stamps = [e.value["stamp"]["sec"] + e.value["stamp"]["nanosec"] / 1e9 for e in events.items]
    assert 104.9 < stamps[0] < 105.2  # 50 votes: 5 s after the first pose
    # ENGAGING once 30 % of the window votes engaged: 60 -1 votes, then 26 +1 (mean -0.4)
    assert 108.5 < stamps[1] < 108.9
    # ENGAGED once the window's mean passes 0.5: 76 votes +1 and 24 -1 of the last 100
    assert 113.5 < stamps[2] < 113.7, engaged.value
