"""Where settings come from: flags over FACING_* variables over defaults; a bad value or a
misspelt variable said in one line that names it."""

from __future__ import annotations

import logging

import pytest

from facing_service.config.sources import load_settings
from facing_service.errors import SettingsError


def test_flag_beats_environment_beats_default():
    env = {"FACING_THRESHOLD_DEG": "30", "FACING_NAMESPACE": "robot1/hri"}
    s = load_settings({"threshold_deg": 25.0}, env)
    assert s.threshold_deg == 25.0 and s.namespace == "robot1/hri"


def test_environment_lists_and_booleans():
    env = {
        "FACING_CONNECT": "tcp/router:7447, tcp/backup:7447",
        "FACING_NO_MULTICAST_SCOUTING": "true",
        "FACING_CFG": "scouting/delay:0;transport/unicast/max_links:2",
        "FACING_MODE": "client",
        "FACING_LOG_LEVEL": "debug",
    }
    s = load_settings({}, env)
    assert s.connect == ["tcp/router:7447", "tcp/backup:7447"]
    assert s.no_multicast_scouting and s.mode == "client" and s.log_level == "DEBUG"
    assert s.cfg == ["scouting/delay:0", "transport/unicast/max_links:2"]


@pytest.mark.parametrize(
    ("flags", "env"),
    [
        ({"threshold_deg": 0.0}, {}),
        ({"threshold_deg": 180.0}, {}),
        ({}, {"FACING_THRESHOLD_DEG": "abc"}),
        ({"hysteresis_deg": -1.0}, {}),
        ({"stale_after_s": 0.0}, {}),
        ({"stale_after_s": float("nan")}, {}),
        ({"max_payload_bytes": 0}, {}),
        ({"namespace": "a/*"}, {}),
        ({"base_frame": "a/b"}, {}),
        ({"mode": "server"}, {}),
        ({"log_level": "loud"}, {}),
        ({"cfg": ["novalue"]}, {}),
    ],
)
def test_bad_settings_are_refused(flags, env):
    with pytest.raises(SettingsError) as refused:
        load_settings(flags, env)
    (field,) = {**flags, **{k.removeprefix("FACING_").lower(): v for k, v in env.items()}}
    assert (f"--{field.replace('_', '-')}=" in str(refused.value)) or (
        f"FACING_{field.upper()}=" in str(refused.value)
    ), "the message names the flag or variable the bad value came from"


def test_a_facing_variable_that_names_no_setting_is_said_in_one_line(caplog):
    """A defect found: FACING_TRESHOLD_DEG=30 (misspelt) was ignored without a word."""
    environ = {
        "FACING_TRESHOLD_DEG": "30",
        "FACING_THRESHOLD_DEG": "25",
        "FACING_HEALTH_CONFIG": "health.json5",  # the health check's, not a setting
        "FACING_TEST_IMAGE": "x",  # the project's test tooling
        "FACING_ZZZ": "1",
        "OTHER": "1",
    }
    with caplog.at_level(logging.WARNING, logger="facing_service"):
        settings = load_settings({}, environ)
    assert settings.threshold_deg == 25
    assert [r.getMessage() for r in caplog.records] == [
        "FACING_TRESHOLD_DEG names no setting and is ignored (did you mean FACING_THRESHOLD_DEG?)",
        "FACING_ZZZ names no setting and is ignored (docs/configuration.md lists them)",
    ]
