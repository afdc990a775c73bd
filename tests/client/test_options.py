"""What FacingClient takes: its own options, each refusal a FacingError naming
the option; the frame given once; the status of the live services."""

from __future__ import annotations

import subprocess
import sys
import typing
from pathlib import Path

import pytest

from facing_service import (
    ClientOptions,
    FacingClient,
    FacingError,
    NoService,
    ServiceStatus,
    SettingsError,
)
from facing_service.client.options import ClientOptionFields
from facing_service.testing import loopback_config

from loopback import endpoint, free_port, send, wait_until, wait_until_answered
from poses import pose_json


def test_a_service_setting_given_to_a_client_is_refused_by_name():
    """The issue's target, run as a user would: the threshold was accepted and did nothing."""
    code = "from facing_service import FacingClient; FacingClient(threshold_deg=50)"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 1
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("facing_service.contract.errors.SettingsError: FacingClient: ")
    assert "threshold_deg= is a setting of the service" in last


@pytest.mark.parametrize(
    ("given", "said"),
    [
        ({"conect": ["tcp/127.0.0.1:7447"]}, "no option conect= (did you mean connect=?)"),
        ({"treshold": 3}, "no option treshold=; it takes namespace, frame,"),
        ({"connect": ["127.0.0.1:7447"]}, "connect=: 127.0.0.1:7447: not <protocol>/"),
        ({"timeout_s": 0}, "timeout_s=: Input should be greater than 0"),
        ({"mode": "router"}, "mode=: Input should be 'peer' or 'client'"),
        ({"cfg": ["scouting"]}, "cfg=: entry 1 is not KEY:VALUE"),
        ({"cfg": ["nonsense/key:1"]}, "FacingClient cfg= nonsense/key:<redacted>: unknown"),
        ({"config": "/no/such.json5"}, "FacingClient config= '/no/such.json5': no such file"),
        ({"frame": "a b"}, "frame=:"),
        ({"tls_root_ca": "/no/ca.pem"}, "tls_root_ca= '/no/ca.pem': no such file"),
        ({"tls_certificate": "me.pem"}, "tls_certificate= and tls_private_key= go together"),
    ],
)
def test_each_bad_option_is_one_facing_error_naming_it(given, said):
    with pytest.raises(SettingsError) as refused:
        FacingClient(**given)
    assert said in str(refused.value)
    assert isinstance(refused.value, FacingError) and "\n" not in str(refused.value)


def test_one_endpoint_or_entry_may_be_given_as_a_string():
    """A defect found: ``FacingClient(connect="tcp/…")`` was refused ("Input should be a valid
    list"); one string is a list of one, never a list of its characters."""
    one = FacingClient(
        connect="tcp/127.0.0.1:7447", listen="tcp/127.0.0.1:0", cfg="scouting/delay:0"
    )
    assert one.options.connect == ["tcp/127.0.0.1:7447"]
    assert one.options.listen == ["tcp/127.0.0.1:0"] and one.options.cfg == ["scouting/delay:0"]
    with pytest.raises(SettingsError, match=r"connect=: 127\.0\.0\.1:7447: not <protocol>/"):
        FacingClient(connect="127.0.0.1:7447")


def test_the_typed_options_and_the_model_name_the_same_things():
    """The keywords a type checker sees are the options the model checks."""
    assert set(typing.get_type_hints(ClientOptionFields)) | {"namespace", "frame"} == set(
        ClientOptions.model_fields
    )


def test_tls_files_reach_the_session_config(tmp_path: Path):
    for name in ("ca.pem", "me.pem", "me.key"):
        (tmp_path / name).write_text("-")
    options = ClientOptions(
        tls_root_ca=tmp_path / "ca.pem",
        tls_certificate=tmp_path / "me.pem",
        tls_private_key=tmp_path / "me.key",
        connect=["tls/localhost:7447"],
    )
    conf = options.zenoh_config()
    assert conf.get_json("transport/link/tls/root_ca_certificate") == f'"{tmp_path}/ca.pem"'
    assert conf.get_json("transport/link/tls/enable_mtls") == "true"
    assert conf.get_json("connect/endpoints") == '["tls/localhost:7447"]'


def test_the_frame_is_given_once(net):
    """Reads default to the client's frame; a client of every frame names one; naming
    another frame than the client's is a mistake said at once (its cache is empty there)."""
    _, ep = net.service()
    tracker = net.client(ep)
    wait_until_answered(tracker, "hri/facing/cam")
    send(tracker, "hri/bodies/ann/pose/cam", pose_json("ann", "cam", x=2.0))
    config = loopback_config(connect=[ep])
    with FacingClient(frame="cam", session_config=config) as one:
        wait_until(lambda: one.bodies_facing() == ["ann"], 5, "ann facing")
        assert one.bodies() == one.bodies("cam") and one.groups() == []
        assert [s.body_id for s in one.query()] == ["ann"]
        with pytest.raises(FacingError, match="watches frame 'cam', not 'base_link'"):
            one.bodies("base_link")
    with FacingClient(session_config=config) as every:
        wait_until(lambda: every.bodies_facing("cam") == ["ann"], 5, "ann facing")
        with pytest.raises(FacingError, match=r"every frame \(\*\): name the frame"):
            every.engagement()


def test_status_names_each_live_service_and_no_service_is_an_error(net):
    _, ep = net.service(instance="front")
    with FacingClient(session_config=loopback_config(connect=[ep])) as client:
        (status,) = client.status()
        assert isinstance(status, ServiceStatus)
        assert (status.instance, status.status) == ("front", "ok")
    nobody = loopback_config(connect=[endpoint(free_port())])
    with (
        FacingClient(session_config=nobody, timeout_s=0.3) as client,
        pytest.raises(NoService, match="answered its status"),
    ):
        client.status()
