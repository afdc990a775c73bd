"""The zenoh session's config from the settings: flags, a config file and --cfg, in that
order of precedence; a key zenoh does not know is refused naming the flag."""

from __future__ import annotations

import json

import pytest

from facing_service.config.session import zenoh_config
from facing_service.config.sources import load_settings
from facing_service.errors import SettingsError


def test_zenoh_config_from_flags_and_cfg(tmp_path):
    file = tmp_path / "z.json5"
    file.write_text('{ mode: "client", connect: { endpoints: ["tcp/127.0.0.1:1"] } }')
    s = load_settings(
        {
            "config": file,
            "listen": ["tcp/127.0.0.1:0"],
            "no_multicast_scouting": True,
            "cfg": ["connect/endpoints:['tcp/127.0.0.1:7448']", "scouting/delay:0"],
        },
        {},
    )
    conf = zenoh_config(s)

    def get(key):
        return json.loads(conf.get_json(key))

    assert get("mode") == "client"  # from the file: no -m flag given
    assert get("listen/endpoints") == ["tcp/127.0.0.1:0"]
    assert get("scouting/multicast/enabled") is False
    assert get("connect/endpoints") == ["tcp/127.0.0.1:7448"]  # --cfg wins, ':' ok
    assert get("scouting/delay") == 0


def test_zenoh_config_refuses_unknown_keys():
    with pytest.raises(SettingsError, match="--cfg no/such/key"):
        zenoh_config(load_settings({"cfg": ["no/such/key:1"]}, {}))


def test_a_session_zenoh_refuses_is_said_in_one_line_naming_the_command(capsys):
    import zenoh

    from facing_service.config.session import opened

    conf = zenoh.Config()
    conf.insert_json5("mode", '"client"')
    conf.insert_json5("connect/endpoints", '["tcp/127.0.0.1:1"]')
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5("connect/timeout_ms", "0")
    assert opened(conf, "record") is None
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("facing-service record: cannot open the zenoh session: ")
