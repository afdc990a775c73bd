"""Nothing secret leaves the process: not in the status any consumer may read, not in logs,
not in error messages. Secrets reach the service through every door a user has: the ``-c``
file, ``--cfg``, ``FACING_CFG``, and the ``#`` config part of an endpoint."""

from __future__ import annotations

import base64
import json
import subprocess
import sys

import pytest

from facing_service.config.disclosure import (
    FILTERED_FIELDS,
    PUBLIC_FIELDS,
    REDACTED,
    is_public_zenoh_key,
    public_settings,
)
from facing_service.config.session import zenoh_config
from facing_service.config.settings import Settings
from facing_service.config.sources import load_settings
from facing_service.errors import SettingsError

SECRETS = (
    "pw-in-file-7f3a",
    "pw-in-flag-91bc",
    "pw-in-env-c04d",
    "/secret/keys/service-private.key",
    base64.b64encode(b"-----BEGIN PRIVATE KEY----- inline").decode(),
    "pw-in-endpoint-5e21",
)


def test_every_setting_is_either_shown_or_filtered():
    """A new setting is not shown until someone decides it may be."""
    assert set(Settings.model_fields) == PUBLIC_FIELDS | FILTERED_FIELDS
    assert not PUBLIC_FIELDS & FILTERED_FIELDS


@pytest.mark.parametrize(
    ("key", "public"),
    [
        ("scouting/delay", True),
        ("connect/timeout_ms", True),
        ("transport/link/tx/lease", True),
        ("transport/auth/usrpwd/password", False),
        ("transport/auth/usrpwd", False),
        ("transport/link/tls/connect_private_key_base64", False),
        ("transport/link/tls", False),
        ("connect/endpoints", False),  # may carry '#' config with inline keys
        ("scoutingx", False),  # whole chunks only
        ("modex", False),
    ],
)
def test_zenoh_keys_are_public_only_when_allow_listed(key, public):
    assert is_public_zenoh_key(key) is public


def test_public_settings_redacts_values_of_unlisted_keys_and_endpoint_configs():
    settings = load_settings(
        {
            "connect": [f"tls/host:7447#connect_private_key_base64={SECRETS[4]}"],
            "cfg": [
                "scouting/delay:0",
                f'transport/auth/usrpwd/password:"{SECRETS[1]}"',
                f'transport/link/tls/connect_private_key:"{SECRETS[3]}"',
            ],
        },
        {},
    )
    shown = public_settings(settings.model_dump(mode="json"))
    assert shown["cfg"] == [
        "scouting/delay:0",
        f"transport/auth/usrpwd/password:{REDACTED}",
        f"transport/link/tls/connect_private_key:{REDACTED}",
    ]
    assert shown["connect"] == [f"tls/host:7447#{REDACTED}"]
    assert shown["threshold_deg"] == 20.0
    assert not any(secret in json.dumps(shown) for secret in SECRETS)


@pytest.mark.parametrize(
    ("flags", "env"),
    [
        ({"cfg": ['transport/auth/usrpwd/password:"unterminated pw-in-flag-91bc']}, {}),
        ({}, {"FACING_CFG": "transport/auth/usrpwd/password:{pw-in-env-c04d"}),
        ({"cfg": ["transport/auth/usrpwd/passwd:'pw-in-flag-91bc'"]}, {}),
        ({"connect": ["tcp/x:1#pw-in-endpoint-5e21"], "cfg": ["nokeyvalue pw-in-flag-91bc"]}, {}),
    ],
    ids=["bad-json5-flag", "bad-json5-env", "unknown-key", "cfg-without-colon"],
)
def test_errors_about_a_secret_setting_never_quote_it(flags, env):
    with pytest.raises(SettingsError) as refused:
        zenoh_config(load_settings(flags, env))
    message = str(refused.value)
    assert "--cfg" in message or "FACING_CFG" in message
    assert not any(secret in message for secret in SECRETS), message
    assert ".rs:" not in message  # no path of zenoh's Rust sources


def test_config_file_errors_name_the_file_and_never_quote_it(tmp_path):
    broken = tmp_path / "broken.json5"
    broken.write_text('{ transport: { auth: { usrpwd: { password: "pw-in-file-7f3a } } } }')
    cases = {
        tmp_path / "missing.json5": "no such file",
        tmp_path: "not a file",
        broken: "not valid JSON5 at line 1",
    }
    for path, why in cases.items():
        with pytest.raises(SettingsError) as refused:
            zenoh_config(load_settings({"config": path}, {}))
        assert str(refused.value) == f"--config {str(path)!r}: {why}" or (
            why in str(refused.value) and str(path) in str(refused.value)
        )
        assert SECRETS[0] not in str(refused.value)


def test_health_errors_never_quote_a_secret():
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "facing_service",
            "health",
            "--cfg",
            f"transport/auth:{{{SECRETS[1]}",
        ],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 2
    assert "--cfg transport/auth:<redacted>" in proc.stderr
    assert SECRETS[1] not in proc.stderr
