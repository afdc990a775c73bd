"""The locked-down deployment of examples/secure, for real: mutual TLS, user/password
authentication and access control on a router, with the real service CLI behind it."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
import trustme
import zenoh

from facing_service.testing import running_cli

from loopback import Recorder, free_port, get, send, wait_until_answered
from poses import pose_json

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "secure"
ROLES = ("tracker", "facing-service", "consumer")


@pytest.fixture
def deployment(tmp_path: Path, net):
    """examples/secure with fresh certificates, its router on a free loopback port."""
    certs = tmp_path / "certs"
    certs.mkdir()
    ca = trustme.CA()
    ca.cert_pem.write_to_path(certs / "ca.pem")
    router_cert = ca.issue_cert("localhost", "127.0.0.1", common_name="router")
    router_cert.private_key_pem.write_to_path(certs / "router.key")
    router_cert.cert_chain_pems[0].write_to_path(certs / "router.pem")
    for role in (*ROLES, "stranger"):
        cert = ca.issue_cert(f"{role}.example", common_name=role)
        cert.private_key_pem.write_to_path(certs / f"{role}.key")
        cert.cert_chain_pems[0].write_to_path(certs / f"{role}.pem")
    for file in EXAMPLE.iterdir():  # absolute paths: every process finds the files
        text = file.read_text().replace('"certs/', f'"{certs}/')
        text = text.replace('"credentials.txt"', f'"{tmp_path / "credentials.txt"}"')
        (tmp_path / file.name).write_text(text)
    port = free_port()
    router_text = (tmp_path / "router.json5").read_text()
    router_text = router_text.replace('"tls/[::]:7447"', f'"tls/127.0.0.1:{port}"')
    net.router(router_text, port=port)
    return tmp_path, f"tls/localhost:{port}"


def session(folder: Path, endpoint: str, role: str, **overrides: str) -> zenoh.Session:
    """A client session from the example config of ``role``, pointed at the router."""
    conf = zenoh.Config.from_file(
        str(folder / f"{'consumer' if role == 'stranger' else role}.json5")
    )
    conf.insert_json5("connect/endpoints", json.dumps([endpoint]))
    for key, value in overrides.items():
        conf.insert_json5(key, value)
    return zenoh.open(conf)


@pytest.fixture
def service(deployment):
    """The real service CLI, configured by examples/secure/service.json5."""
    folder, endpoint = deployment
    config = str(folder / "service.json5")
    flags = ("-c", config, "-e", endpoint, "--base-frame", "cam", "--instance", "secure")
    with running_cli("run", *flags) as proc:
        yield proc


@pytest.fixture
def tracker_and_consumer(deployment, service):
    """Sessions of a tracker and a consumer, once the service answers the consumer."""
    folder, endpoint = deployment
    tracker = session(folder, endpoint, "tracker")
    consumer = session(folder, endpoint, "consumer")
    try:
        wait_until_answered(consumer, "hri/facing/cam", timeout=20)
        yield tracker, consumer
    finally:
        tracker.close()
        consumer.close()


def test_the_authorised_flow_works_end_to_end(tracker_and_consumer):
    tracker, consumer = tracker_and_consumer
    results = Recorder(consumer, "hri/bodies/*/facing/**")
    try:
        send(tracker, "hri/bodies/alice/pose/cam", pose_json("alice", "cam", off_deg=5.0))
        (result,) = results.wait_for(lambda i: i.kind == "put")
        assert result.value["body_id"] == "alice" and result.value["facing"]
        (frame,) = get(consumer, "hri/facing/**")
        assert frame[1]["bodies_facing"] == ["alice"]
        (status,) = get(consumer, "hri/services/facing/*/status")
        assert status[1]["instance"] == "secure" and status[1]["status"] == "ok"
        tokens = [str(r.ok.key_expr) for r in consumer.liveliness().get("hri/services/facing/*")]
        assert tokens == ["hri/services/facing/secure"]
    finally:
        results.close()


@pytest.mark.parametrize(
    "overrides",
    [
        {"transport/auth/usrpwd/user": "null", "transport/auth/usrpwd/password": "null"},
        {"transport/auth/usrpwd/password": '"wrong"'},
        {
            "transport/link/tls/connect_certificate": "null",
            "transport/link/tls/connect_private_key": "null",
        },
    ],
    ids=["no-credentials", "wrong-password", "no-client-certificate"],
)
def test_a_client_without_valid_credentials_cannot_connect(deployment, overrides):
    folder, endpoint = deployment
    with pytest.raises(zenoh.ZError):
        session(folder, endpoint, "consumer", **overrides).close()


def test_a_certificate_for_another_name_gets_no_rights(deployment, service):
    """A valid password with someone else's certificate matches no ACL subject."""
    folder, endpoint = deployment
    cert = {
        "transport/link/tls/connect_certificate": json.dumps(str(folder / "certs/stranger.pem")),
        "transport/link/tls/connect_private_key": json.dumps(str(folder / "certs/stranger.key")),
    }
    consumer = session(folder, endpoint, "consumer")
    stranger = session(folder, endpoint, "stranger", **cert)
    try:
        wait_until_answered(consumer, "hri/facing/cam", timeout=20)  # the service is up
        assert stranger.info.routers_zid()  # connected: TLS and password were accepted
        assert get(stranger, "hri/facing/**", timeout=2) == []  # but it may not ask
        assert get(consumer, "hri/facing/**", timeout=2)  # while the consumer may
    finally:
        stranger.close()
        consumer.close()


def test_authenticated_consumers_cannot_inject_and_trackers_cannot_forge(tracker_and_consumer):
    tracker, consumer = tracker_and_consumer
    frames = Recorder(consumer, "hri/facing/**")
    try:
        send(consumer, "hri/bodies/mallory/pose/cam", pose_json("mallory", "cam"))
        forged = {
            "frame_id": "cam",
            "stamp": None,
            "bodies_facing": ["forged"],
            "bodies_tracked": ["forged"],
        }
        tracker.put("hri/facing/cam", json.dumps(forged))
        send(tracker, "hri/bodies/alice/pose/cam", pose_json("alice", "cam"))
        frames.wait_for(lambda i: i.value["bodies_tracked"] == ["alice"])
        time.sleep(0.5)  # leave time for anything the policy failed to stop
        assert all("forged" not in i.value["bodies_tracked"] for i in frames.items)
        (frame,) = get(consumer, "hri/facing/cam")
        assert frame[1]["bodies_tracked"] == ["alice"]  # mallory never reached the service
        (status,) = get(consumer, "hri/services/facing/*/status")
        assert status[1]["counters"]["samples_accepted"] == 1
    finally:
        frames.close()


def test_examples_are_valid_zenoh_configs():
    for name in ("router.json5", "service.json5", "tracker.json5", "consumer.json5"):
        zenoh.Config.from_file(str(EXAMPLE / name))  # raises on an unknown key or value
