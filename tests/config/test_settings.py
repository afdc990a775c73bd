"""The settings' defaults: what a service started with no flag and no variable runs with."""

from __future__ import annotations

from facing_service.config.sources import load_settings


def test_defaults():
    s = load_settings({}, {})
    assert (s.namespace, s.base_frame, s.threshold_deg, s.hysteresis_deg) == ("hri", "*", 20, 5)
    assert (s.stale_after_s, s.max_payload_bytes, s.log_level) == (2.0, 65536, "INFO")
    assert s.mode is None and s.connect == [] and not s.no_multicast_scouting
