"""A session kept as MCAP (``record``) and played into a service again (``replay
SESSION.mcap``): written by Foxglove's SDK, read back by ``mcap``, the format's reference
Python reader (an independent implementation), and the replay judged against the live
run."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

from facing_service.client.sim import Crowd, TrackerPublisher, simulate
from facing_service.contract.schemas import json_schemas
from facing_service.testing import LOOPBACK_FLAGS, running_cli
from facing_service.tools.session_mcap import DELETES, PROFILE, schema_file
from facing_service.tools.session_record import SessionRecorder

from loopback import endpoint


def read(path: Path) -> list[tuple[str, str, dict]]:
    """(topic, schema name, message) of every message, in log time order."""
    from mcap.reader import make_reader

    with path.open("rb") as stream:
        reader = make_reader(stream)
        assert reader.get_header().profile == PROFILE
        return [(c.topic, s.name, json.loads(m.data))
                for s, c, m in reader.iter_messages(log_time_order=True)]  # fmt: skip


def test_each_key_of_the_contract_is_kept_under_its_schema():
    assert schema_file("hri", "hri/bodies/ann/pose/cam") == "pose.schema.json"
    assert schema_file("hri", "hri/bodies/ann/facing/cam") == "facing_state.schema.json"
    assert schema_file("hri", "hri/groups/cam/3") == "group_state.schema.json"
    assert schema_file("hri", "hri/services/facing/x/status") == "status.schema.json"
    assert schema_file("hri", "hri/facing/~wake") == "frame_facing.schema.json"
    assert schema_file("hri", "other/bodies/ann/pose/cam") is None
    assert schema_file("hri", "hri/bodies/ann") is None


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (["record", "x.json"], "a session is an .mcap file"),
        (["record", "/no/such/dir/x.mcap"], "no such folder"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(args, said):
    proc = subprocess.run([sys.executable, "-m", "facing_service", *args, *LOOPBACK_FLAGS],
                          capture_output=True, text=True, timeout=30)  # fmt: skip
    assert proc.returncode == 2 and said in proc.stderr, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


def crowd_into(session, seconds: float) -> TrackerPublisher:
    publish = TrackerPublisher(session)
    crowd = Crowd(people=5, seed=3, start_s=1_800_000_000.0)
    simulate(publish, crowd, "cam", "hri", 30.0, seconds)
    return publish


def facing_said(messages) -> set[tuple]:
    return {
        (topic, m["stamp"]["sec"], m["stamp"]["nanosec"], m["facing"], round(m["angle_deg"], 9))
        for topic, schema, m in messages
        if schema == "facing_state"
    }


def events_said(messages) -> list[tuple]:
    return sorted(
        (m["body_id"], m["stamp"]["sec"], m["stamp"]["nanosec"], m["level"])
        for _, schema, m in messages
        if schema == "engagement_event"
    )


@pytest.mark.slow
def test_a_session_recorded_and_replayed_gives_the_same_results(net, tmp_path):
    """Recorded live (a crowd for 8 s into a service); played by the CLI into a fresh
    service, kept again with --record: every pose and every result is in the first file,
    and the second holds the same results at the same stamps, the same level changes."""
    router = net.router()  # (peers do not forward one peer's poses to another)
    ep = endpoint(router.port)
    net.service(mode="client", connect=[ep], listen=[])
    tracker, listener = net.client(ep, mode="client"), net.client(ep, mode="client")
    first = tmp_path / "first.mcap"
    recorder = SessionRecorder(listener, "hri", first)
    time.sleep(1.0)
    published = crowd_into(tracker, 8.0)
    time.sleep(1.5)  # the last results, and a status or two
    messages, topics = recorder.close()
    live = read(first)
    assert len(live) == messages and topics > 10
    poses = [m for _, schema, m in live if schema == "pose"]
    assert len(poses) == published.poses  # every pose the tracker sent
    assert sum(topic == DELETES for topic, _, _ in live) >= published.deletes
    assert {schema for _, schema, _ in live} >= {
        "pose", "facing_state", "engagement_state", "frame_facing", "status", "delete"
    }  # fmt: skip
    assert facing_said(live) and len({t for t, s, _ in live if s == "facing_state"}) >= 5

    other = net.router()
    fresh = endpoint(other.port)
    net.service(mode="client", connect=[fresh], listen=[])
    second = tmp_path / "second.mcap"
    flags = ("--record", str(second), "-m", "client", "-e", fresh, *LOOPBACK_FLAGS)
    with running_cli("replay", str(first), *flags) as proc:
        assert proc.wait(timeout=60) == 0, proc.stdout.read()
        output = proc.stdout.read()
    assert f"sent {len(poses)} poses" in output, output
    again = read(second)
    assert [m for _, s, m in again if s == "pose"] == poses
    assert facing_said(again) == facing_said(live)
    assert events_said(again) == events_said(live)


def test_the_schemas_kept_are_the_contracts():
    """Each schema record is the wire contract's own JSON Schema (``schemas/``)."""
    from facing_service.tools.session_mcap import schema_bytes

    for name, schema in json_schemas().items():
        assert json.loads(schema_bytes(name)) == schema
        on_disk = Path(__file__).resolve().parents[2] / "schemas" / name
        assert json.loads(on_disk.read_text()) == schema
