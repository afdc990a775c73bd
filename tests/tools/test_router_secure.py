"""The locked-down deployment of examples/secure, tried as an attacker would: mutual TLS,
user/password authentication and access control on the project's own router command
(``facing-service router``), with the real service CLI behind it."""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import ssl
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import trustme
import zenoh

from facing_service import FacingClient
from facing_service.contract import keys
from facing_service.testing import free_port, running_cli

from loopback import Recorder, get, results, send, send_delete, wait_until_answered
from poses import pose_json
from routers import wait_for_port
from system_packages import require

pytestmark = pytest.mark.slow  # processes, recordings or seconds-long scenarios


EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "secure"
ROLES = ("tracker", "facing-service", "consumer", "health")
PASSWORDS = {  # as examples/secure ships them (credentials.txt and the client configs)
    "tracker": "change-me-tracker",
    "facing-service": "change-me-service",
    "consumer": "change-me-consumer",
    "health": "change-me-health",
}


def _write_cert(cert: trustme.LeafCert, folder: Path, name: str) -> None:
    cert.private_key_pem.write_to_path(folder / f"{name}.key")
    cert.cert_chain_pems[0].write_to_path(folder / f"{name}.pem")


class Deployment:
    """An example deployment (examples/secure unless told) copied to a folder, with fresh
    certificates for its ``roles`` and a free port; a "stranger" connects with the
    config of ``stranger_as``."""

    def __init__(
        self,
        folder: Path,
        example: Path = EXAMPLE,
        roles: tuple[str, ...] = ROLES,
        stranger_as: str = "consumer",
    ) -> None:
        self.folder = folder
        self.port = free_port()
        self.endpoint = f"tls/localhost:{self.port}"
        self.stranger_as = stranger_as
        shutil.copytree(example, folder, dirs_exist_ok=True, ignore=shutil.ignore_patterns("certs"))
        certs = folder / "certs"
        certs.mkdir()
        ca = trustme.CA()
        ca.cert_pem.write_to_path(certs / "ca.pem")
        _write_cert(ca.issue_cert("localhost", "127.0.0.1", common_name="router"), certs, "router")
        for role in (*roles, "stranger"):
            _write_cert(ca.issue_cert(f"{role}.example", common_name=role), certs, role)
        # Certificates of another CA, for the same names: an attacker's own PKI.
        rogue = trustme.CA()
        rogue.cert_pem.write_to_path(certs / "rogue-ca.pem")
        _write_cert(
            rogue.issue_cert("localhost", "127.0.0.1", common_name="router"), certs, "rogue-router"
        )
        _write_cert(
            rogue.issue_cert("consumer.example", common_name="consumer"), certs, "rogue-consumer"
        )

    def path(self, name: str) -> str:
        return str(self.folder / name)

    def session(self, role: str, endpoint: str | None = None, **overrides: str) -> zenoh.Session:
        """A client session from the example config of ``role``, pointed at the router.
        Relative paths in the example resolve from the deployment folder."""
        conf_role = self.stranger_as if role == "stranger" else role
        text = (self.folder / f"{conf_role}.json5").read_text()
        conf = zenoh.Config.from_json5(text.replace('"certs/', f'"{self.folder}/certs/'))
        conf.insert_json5("connect/endpoints", json.dumps([endpoint or self.endpoint]))
        for key, value in overrides.items():
            conf.insert_json5(key, value)
        return zenoh.open(conf)

    def refuses(self, endpoint: str | None = None, **overrides: str) -> None:
        """A consumer connecting with ``overrides`` is refused at ``endpoint`` by whoever
        listens there: zenoh names that endpoint (not a config error), and the
        deployment's own consumer connects to the deployment's router right after (the
        positive control: the router is up, so the refusal is the credentials')."""
        where = endpoint or self.endpoint
        with pytest.raises(zenoh.ZError) as refused:
            self.session("consumer", endpoint=endpoint, **overrides).close()
        assert f"Unable to connect to any of [Single({where})]" in str(refused.value)
        with self.session("consumer") as allowed:
            assert allowed.info.routers_zid(), "the deployment's router refuses everyone"

    def cert_of(self, name: str) -> dict[str, str]:
        return {
            "transport/link/tls/connect_certificate": json.dumps(self.path(f"certs/{name}.pem")),
            "transport/link/tls/connect_private_key": json.dumps(self.path(f"certs/{name}.key")),
        }


def _router_flags(port: int) -> tuple[str, ...]:
    return ("router", "-c", "router.json5", "-l", f"tls/127.0.0.1:{port}")


@pytest.fixture
def deployment(tmp_path: Path) -> Iterator[Deployment]:
    """The example's router, run by ``facing-service router`` from the example's folder
    (so its relative paths are exercised as a user would run it)."""
    site = Deployment(tmp_path / "secure")
    with running_cli(*_router_flags(site.port), cwd=site.folder) as router:
        wait_for_port(site.port)
        assert router.poll() is None
        yield site


@pytest.fixture
def service(deployment: Deployment) -> Iterator[subprocess.Popen[str]]:
    """The real service CLI, configured by examples/secure/service.json5."""
    flags = ("-c", "service.json5", "-e", deployment.endpoint, "--base-frame", "cam")
    with running_cli("run", *flags, "--instance", "secure", cwd=deployment.folder) as proc:
        yield proc


@pytest.fixture
def tracker_and_consumer(deployment, service):
    """Sessions of a tracker and a consumer, once the service answers the consumer."""
    tracker = deployment.session("tracker")
    consumer = deployment.session("consumer")
    try:
        wait_until_answered(consumer, "hri/facing/cam", timeout=20)
        yield tracker, consumer
    finally:
        tracker.close()
        consumer.close()


# -- what the deployment guarantees, end to end ------------------------------------------


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


def test_engagement_reaches_consumers_under_the_policy(deployment, tracker_and_consumer):
    """Every output, not only the facing keys: FacingClient.on_engaged fires, engagement
    states can be subscribed to and queried."""
    tracker, consumer = tracker_and_consumer
    states = Recorder(consumer, "hri/bodies/*/engagement/*")
    engaged = threading.Event()
    certs = deployment.folder / "certs"
    client = FacingClient(  # the client's own options, over the example's config file
        "hri",
        "cam",
        connect=[deployment.endpoint],
        config=deployment.folder / "consumer.json5",
        tls_root_ca=certs / "ca.pem",
        tls_certificate=certs / "consumer.pem",
        tls_private_key=certs / "consumer.key",
    )
    try:
        client.open()
        client.on_engaged(lambda event: engaged.set())  # on an open client
        for i in range(90):  # facing from 1.2 m for up to 3 s at 30 Hz
            pose = pose_json("bob", "cam", x=1.2, sec=1 + i // 30, nanosec=(i % 30) * 33_000_000)
            send(tracker, "hri/bodies/bob/pose/cam", pose)
            if engaged.wait(1 / 30):
                break
        assert engaged.is_set(), "on_engaged never fired under the secure policy"
        states.wait_for(lambda i: i.kind == "put" and i.value["level"] == "ENGAGED")
        (state,) = get(consumer, "hri/bodies/*/engagement/cam")
        assert state[1]["body_id"] == "bob"
    finally:
        client.close()
        states.close()


# -- who cannot connect at all -----------------------------------------------------------


@pytest.mark.parametrize(
    "overrides",
    [
        {"transport/auth/usrpwd/user": "null", "transport/auth/usrpwd/password": "null"},
        {"transport/auth/usrpwd/password": '"wrong"'},
        {"transport/auth/usrpwd/password": json.dumps(PASSWORDS["tracker"])},
        {
            "transport/link/tls/connect_certificate": "null",
            "transport/link/tls/connect_private_key": "null",
        },
    ],
    ids=["no-credentials", "wrong-password", "another-users-password", "no-client-certificate"],
)
def test_a_client_without_valid_credentials_cannot_connect(deployment, overrides):
    deployment.refuses(**overrides)


def test_the_router_itself_refuses_a_client_that_presents_no_certificate(deployment):
    """Not the client library refusing to build its TLS setup: a plain TLS client that
    trusts the CA completes its handshake, and the router then ends it with TLS's
    'certificate required' alert. The same client with a certificate is kept talking."""
    context = ssl.create_default_context(cafile=deployment.path("certs/ca.pem"))

    def first_read(tls_context: ssl.SSLContext) -> bytes | Exception:
        with (
            socket.create_connection(("127.0.0.1", deployment.port), timeout=5) as raw,
            tls_context.wrap_socket(raw, server_hostname="localhost") as tls,
        ):
            tls.settimeout(1.5)
            try:
                return tls.recv(1)
            except (ssl.SSLError, TimeoutError) as error:
                return error

    refused = first_read(context)
    assert isinstance(refused, ssl.SSLError), refused
    assert "CERTIFICATE_REQUIRED" in str(refused) or "certificate required" in str(refused)
    context.load_cert_chain(
        deployment.path("certs/consumer.pem"), deployment.path("certs/consumer.key")
    )
    assert isinstance(first_read(context), TimeoutError)  # accepted: waits for zenoh's hello


def test_a_certificate_from_another_ca_is_refused(deployment):
    deployment.refuses(**deployment.cert_of("rogue-consumer"))


def test_plain_tcp_to_the_tls_port_is_refused(deployment):
    deployment.refuses(endpoint=f"tcp/127.0.0.1:{deployment.port}")


def test_clients_refuse_a_rogue_router_with_another_cas_certificate(deployment, tmp_path):
    """A router impersonating the site (same host name, another CA) gets no client."""
    rogue_port = free_port()
    rogue = (deployment.folder / "router.json5").read_text()
    rogue = rogue.replace('"certs/router.', '"certs/rogue-router.').replace(
        '"certs/ca.pem"', '"certs/rogue-ca.pem"'
    )
    (deployment.folder / "rogue.json5").write_text(rogue)
    flags = ("router", "-c", "rogue.json5", "-l", f"tls/127.0.0.1:{rogue_port}")
    with running_cli(*flags, cwd=deployment.folder):
        wait_for_port(rogue_port)
        deployment.refuses(endpoint=f"tls/localhost:{rogue_port}")


# -- who connects, but gets no rights ----------------------------------------------------


@pytest.mark.parametrize(
    ("role", "certificate"),
    [("stranger", "stranger"), ("consumer", "tracker"), ("tracker", "consumer")],
    ids=[
        "certificate-of-an-unknown-name",
        "consumer-password-tracker-cert",
        "tracker-password-consumer-cert",
    ],
)
def test_mixed_identities_get_no_rights(deployment, service, role, certificate):
    """A valid password with someone else's certificate matches no ACL subject."""
    consumer = deployment.session("consumer")
    tracker = deployment.session("tracker")
    mixed = deployment.session(role, **deployment.cert_of(certificate))
    try:
        wait_until_answered(consumer, "hri/facing/cam", timeout=20)  # the service is up
        assert mixed.info.routers_zid()  # connected: TLS and password were accepted
        assert get(mixed, "hri/facing/**", timeout=2) == []  # but it may not ask
        send(mixed, "hri/bodies/eve/pose/cam", pose_json("eve", "cam"))
        # The positive control: a legitimate pose sent after the forged one gets in.
        send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam"))
        frame = wait_for_frame(consumer, lambda tracked: "bob" in tracked)
        assert frame["bodies_tracked"] == ["bob"]  # nor inject: eve never got in
    finally:
        mixed.close()
        tracker.close()
        consumer.close()


def wait_for_frame(consumer, condition, timeout: float = 10.0) -> dict:
    """The aggregate of frame cam, once its tracked bodies meet ``condition``."""
    deadline = time.monotonic() + timeout
    while True:
        frames = get(consumer, "hri/facing/cam")
        if frames and condition(frames[0][1]["bodies_tracked"]):
            return frames[0][1]
        assert time.monotonic() < deadline, f"frame cam never met the condition: {frames}"
        time.sleep(0.05)


def test_authenticated_consumers_cannot_inject_and_trackers_cannot_forge(tracker_and_consumer):
    tracker, consumer = tracker_and_consumer
    frames = Recorder(consumer, "hri/facing/**")
    results = Recorder(consumer, "hri/bodies/*/facing/**")
    try:
        send(tracker, "hri/bodies/alice/pose/cam", pose_json("alice", "cam"))
        frames.wait_for(lambda i: i.value["bodies_tracked"] == ["alice"])
        # A consumer injects a person and deletes a real one; a tracker forges results.
        send(consumer, "hri/bodies/mallory/pose/cam", pose_json("mallory", "cam"))
        send_delete(consumer, "hri/bodies/alice/pose/cam")
        forged = {
            "frame_id": "cam",
            "stamp": None,
            "bodies_facing": ["forged"],
            "bodies_tracked": ["forged"],
        }
        tracker.put("hri/facing/cam", json.dumps(forged))
        send_delete(tracker, "hri/bodies/alice/facing/cam")
        tracker.put("hri/bodies/alice/engagement/cam", b'{"level": "ENGAGED"}')
        send(tracker, "hri/bodies/alice/pose/cam", pose_json("alice", "cam", sec=2))
        results.wait_for(lambda i: i.kind == "put" and i.value["stamp"]["sec"] == 2)
        time.sleep(0.5)  # leave time for anything the policy failed to stop
        assert all("forged" not in i.value["bodies_tracked"] for i in frames.items)
        assert all(i.kind == "put" for i in results.items), "a forged DELETE got through"
        (frame,) = get(consumer, "hri/facing/cam")
        assert frame[1]["bodies_tracked"] == ["alice"]  # mallory never reached the service
        (status,) = get(consumer, "hri/services/facing/*/status")
        assert status[1]["counters"]["samples_accepted"] == 2
        assert status[1]["counters"]["deletes_published"] == 0  # alice was never deleted
    finally:
        frames.close()
        results.close()


def test_fake_queryables_and_service_tokens_never_reach_consumers(tracker_and_consumer):
    tracker, consumer = tracker_and_consumer

    def forge(query: zenoh.Query) -> None:
        query.reply("hri/facing/cam", json.dumps({"bodies_tracked": ["forged"]}))

    fake = tracker.declare_queryable("hri/facing/cam", forge)
    token = tracker.liveliness().declare_token("hri/services/facing/impostor")
    try:
        time.sleep(0.5)
        replies = get(consumer, "hri/facing/cam")
        assert len(replies) == 1 and "forged" not in replies[0][1]["bodies_tracked"]
        tokens = [str(r.ok.key_expr) for r in consumer.liveliness().get("hri/services/facing/*")]
        assert tokens == ["hri/services/facing/secure"]
    finally:
        token.undeclare()
        fake.undeclare()


# -- nothing secret leaves the service ---------------------------------------------------


@pytest.mark.parametrize("door", ["--cfg", "FACING_CFG"])
def test_the_status_and_logs_disclose_no_credential(deployment, door):
    """The service's password and key path given on top of its config file, as a user
    would to keep them out of the file; a consumer reads the status; the service logs
    at DEBUG. Neither holds the password, the key's path or the key itself."""
    key_path = deployment.path("certs/facing-service.key")
    entries = [
        f'transport/auth/usrpwd/password:"{PASSWORDS["facing-service"]}"',
        f'transport/link/tls/connect_private_key:"{key_path}"',
    ]
    flags = ["-c", "service.json5", "-e", deployment.endpoint, "--base-frame", "cam"]
    env = {}
    if door == "--cfg":
        flags += [arg for entry in entries for arg in ("--cfg", entry)]
    else:
        env["FACING_CFG"] = ";".join(entries)
    with (
        running_cli("run", *flags, "--log-level", "DEBUG", env=env, cwd=deployment.folder) as proc,
        deployment.session("consumer") as consumer,
    ):
        wait_until_answered(consumer, "hri/facing/cam", timeout=20)
        replies = list(consumer.get("hri/services/facing/*/status"))
        (raw,) = [r.ok.payload.to_string() for r in replies if r.ok is not None]
        proc.send_signal(signal.SIGTERM)  # its whole log, shutdown included
        output, _ = proc.communicate(timeout=10)  # read while it writes: DEBUG is verbose
    key_body = Path(key_path).read_text().splitlines()[1]  # a line of the key's base64
    for secret in (PASSWORDS["facing-service"], key_path, key_body):
        assert secret not in raw, f"the status discloses {secret!r}"
        assert secret not in output, f"the log discloses {secret!r}"
    assert "transport/auth/usrpwd/password:<redacted>" in json.loads(raw)["config"]["cfg"]


# -- health checks in a secure deployment ------------------------------------------------


def _health(site: Deployment, **env: str) -> subprocess.CompletedProcess[str]:
    base = {"FACING_CONFIG": "service.json5", "FACING_CONNECT": site.endpoint}
    return subprocess.run(
        [sys.executable, "-m", "facing_service", "health", "--json", "--timeout", "3"],
        env={**os.environ, **base, **env},
        cwd=site.folder,
        capture_output=True,
        text=True,
        timeout=60,
    )


def test_health_passes_with_its_own_identity_and_fails_without_a_service(deployment):
    """As the container runs it: the service's FACING_* variables (its password in
    FACING_CFG too), plus FACING_HEALTH_CONFIG for the health check's identity."""
    password = f'transport/auth/usrpwd/password:"{PASSWORDS["facing-service"]}"'
    env = {"FACING_HEALTH_CONFIG": "health.json5", "FACING_CFG": password}
    absent = _health(deployment, **env)
    assert absent.returncode == 1, absent.stdout + absent.stderr
    with running_cli(
        "run",
        "-c",
        "service.json5",
        "-e",
        deployment.endpoint,
        "--instance",
        "secure",
        cwd=deployment.folder,
    ):
        with deployment.session("consumer") as consumer:
            wait_until_answered(consumer, "hri/services/facing/*/status", timeout=20)
        healthy = _health(deployment, **env)
        assert healthy.returncode == 0, healthy.stdout + healthy.stderr
        assert json.loads(healthy.stdout.splitlines()[0])["instance"] == "secure"
        # The service's own identity may not ask: the failure says what to do.
        refused = _health(deployment)
        assert refused.returncode == 1
        assert "FACING_HEALTH_CONFIG" in refused.stderr


def test_the_health_identity_may_only_ask_for_the_status(deployment, tracker_and_consumer):
    tracker, consumer = tracker_and_consumer
    send(tracker, "hri/bodies/alice/pose/cam", pose_json("alice", "cam"))
    with deployment.session("health") as health:
        assert get(health, "hri/services/facing/*/status")  # allowed
        assert get(health, "hri/facing/**", timeout=2) == []  # results: not its business
        send(health, "hri/bodies/eve/pose/cam", pose_json("eve", "cam"))
        # The positive control: a legitimate pose sent after the forged one gets in.
        send(tracker, "hri/bodies/bob/pose/cam", pose_json("bob", "cam"))
        frame = wait_for_frame(consumer, lambda tracked: "bob" in tracked)
        assert frame["bodies_tracked"] == ["alice", "bob"]  # eve never got in
        (status,) = get(health, "hri/services/facing/*/status")
        assert status[1]["counters"]["samples_accepted"] == 2
        assert sum(status[1]["rejected"].values()) == 0  # refused by the router, not us


# -- the policy covers every key space of keys.py ----------------------------------------


def _policy() -> dict[str, list[dict]]:
    """The rules each subject is given, from the shipped router config."""
    acl = json.loads(
        zenoh.Config.from_file(str(EXAMPLE / "router.json5")).get_json("access_control")
    )
    rules = {rule["id"]: rule for rule in acl["rules"]}
    given: dict[str, list[dict]] = {}
    for policy in acl["policies"]:
        for subject in policy["subjects"]:
            given.setdefault(subject, []).extend(rules[r] for r in policy["rules"])
    return given


def _allowed(rules: list[dict], flow: str, message: str, key: str) -> bool:
    return any(
        rule["permission"] == "allow"
        and flow in rule["flows"]
        and message in rule["messages"]
        and any(zenoh.KeyExpr(ke).includes(zenoh.KeyExpr(key)) for ke in rule["key_exprs"])
        for rule in rules
    )


# What each side of the router must be allowed for each kind of key space: the service
# (subject "facing-service") and the consumers (subject "consumers").
_NEEDS = {
    "published": {
        "facing-service": [
            ("ingress", "put"),
            ("ingress", "delete"),
            ("egress", "declare_subscriber"),
        ],
        "consumers": [("ingress", "declare_subscriber"), ("egress", "put"), ("egress", "delete")],
    },
    "served": {
        "facing-service": [
            ("ingress", "declare_queryable"),
            ("ingress", "reply"),
            ("egress", "query"),
        ],
        "consumers": [("ingress", "query"), ("egress", "reply"), ("egress", "declare_queryable")],
    },
    "token": {
        "facing-service": [("ingress", "liveliness_token")],
        "consumers": [
            ("ingress", "liveliness_query"),
            ("ingress", "declare_liveliness_subscriber"),
            ("egress", "liveliness_token"),
        ],
    },
}


def test_the_shipped_policy_covers_every_key_space_the_service_has():
    policy = _policy()
    spaces = {
        "published": keys.published_spaces("hri"),
        "served": keys.served_spaces("hri"),
        "token": (keys.service_token("hri", "*"),),
    }
    missing = [
        f"{subject} {flow} {message} {space}"
        for kind, needs in _NEEDS.items()
        for subject, pairs in needs.items()
        for space in spaces[kind]
        for flow, message in pairs
        if not _allowed(policy[subject], flow, message, space)
    ]
    assert missing == []
    health = policy["health-checks"]
    status = keys.status_key("hri", "*")
    assert _allowed(health, "ingress", "query", status) and _allowed(
        health, "egress", "reply", status
    )
    assert not any(
        _allowed(health, "ingress", "query", space) for space in keys.published_spaces("hri")
    )
    # Trackers may publish poses and nothing of the service's.
    trackers = policy["trackers"]
    assert _allowed(trackers, "ingress", "put", keys.pose_key("hri", body_id="*", frame_id="*"))
    assert not any(
        _allowed(trackers, "ingress", m, s)
        for s in keys.published_spaces("hri")
        for m in ("put", "delete")
    )


def test_every_key_the_service_publishes_lies_in_a_published_space(net):
    """keys.published_spaces is what the ACL check above relies on: a key space the
    service starts publishing on without listing it there fails here."""
    _service, ep = net.service(engage_dwell_s=0.0)
    client = net.client(ep)
    everything = net.recorder(client, "**")
    wait_until_answered(client, "hri/facing/cam")
    for i in range(40):
        send(
            client,
            "hri/bodies/a/pose/cam",
            pose_json("a", "cam", x=1.0, sec=1, nanosec=i * 25_000_000),
        )
    send_delete(client, "hri/bodies/a/pose/cam")
    everything.wait_for(lambda i: i.key.startswith("hri/events/"))
    everything.wait_for(lambda i: i.kind == "delete" and "/facing/" in i.key)
    published = {i.key for i in everything.items if not i.key.startswith("hri/bodies/a/pose/")}
    spaces = [zenoh.KeyExpr(s) for s in keys.published_spaces("hri")]
    assert published and all(any(s.includes(zenoh.KeyExpr(k)) for s in spaces) for k in published)


def test_examples_are_valid_zenoh_configs():
    for name in (
        "router.json5",
        "service.json5",
        "tracker.json5",
        "consumer.json5",
        "health.json5",
    ):
        conf = zenoh.Config.from_file(str(EXAMPLE / name))  # raises on a bad key or value
        mode = json.loads(conf.get_json("mode"))
        assert mode == ("router" if name == "router.json5" else "client"), (name, mode)


def test_every_password_in_the_example_is_listed_in_its_readme():
    readme = (EXAMPLE / "README.md").read_text()
    for role, password in {**PASSWORDS, "router": "change-me-router"}.items():
        assert f"`{password}`" in readme, f"{role}'s password is not listed"
    for line in (EXAMPLE / "credentials.txt").read_text().splitlines():
        assert line.split(":", 1)[1] in PASSWORDS.values()


# -- the recipe, copied from the README into sh --------------------------------------------


def _recipe() -> str:
    """The certificate recipe block of examples/secure/README.md, as a user copies it."""
    text = (EXAMPLE / "README.md").read_text()
    block = text.split("<!-- recipe -->", 1)[1].split("```sh\n", 1)[1].split("```", 1)[0]
    return block


def test_the_recipe_runs_in_sh_and_makes_a_working_deployment(tmp_path):
    """From examples/secure, in POSIX sh: the certificates it makes work with the shipped
    configs and the router command, for the service, a tracker, a consumer and health."""
    require("openssl")
    folder = tmp_path / "secure"
    shutil.copytree(EXAMPLE, folder, ignore=shutil.ignore_patterns("certs"))
    made = subprocess.run(
        ["sh", "-eu", "-c", _recipe()], cwd=folder, capture_output=True, text=True, timeout=120
    )
    assert made.returncode == 0, made.stderr
    for role in ("router", *ROLES):
        assert (folder / "certs" / f"{role}.pem").is_file() and (
            folder / "certs" / f"{role}.key"
        ).is_file()
        assert (folder / "certs" / f"{role}.key").stat().st_mode & 0o077 == 0, (
            "a private key is readable by others"
        )
    assert not (folder / "certs" / "ca.key").exists(), (
        "the recipe leaves the CA key beside the configs"
    )
    site = Deployment.__new__(Deployment)
    site.folder, site.port = folder, free_port()
    site.endpoint = f"tls/localhost:{site.port}"
    with running_cli(*_router_flags(site.port), cwd=folder):
        wait_for_port(site.port)
        flags = ("-c", "service.json5", "-e", site.endpoint, "--base-frame", "cam")
        with (
            running_cli("run", *flags, cwd=folder),
            site.session("tracker") as tracker,
            site.session("consumer") as consumer,
        ):
            wait_until_answered(consumer, "hri/facing/cam", timeout=20)
            send(tracker, "hri/bodies/alice/pose/cam", pose_json("alice", "cam"))
            deadline = time.monotonic() + 5
            while not results(get(consumer, "hri/bodies/alice/facing/cam")):
                assert time.monotonic() < deadline, "no result through the recipe's deployment"
                time.sleep(0.05)
            healthy = _health(site, FACING_HEALTH_CONFIG="health.json5")
            assert healthy.returncode == 0, healthy.stderr


def test_certificates_and_keys_are_ignored_by_git():
    root = EXAMPLE.parent.parent
    for path in (
        "examples/secure/certs/ca.key",
        "examples/secure/certs/router.pem",
        "examples/secure/x.key",
    ):
        ignored = subprocess.run(["git", "check-ignore", "-q", path], cwd=root, check=False)
        assert ignored.returncode == 0, f"{path} is not ignored by git"
