"""What the settings make of the core's parameters: one rule for everyone with
--engagement rule, a head's score that engages exactly where its cone begins, the scene's
facing rule the bodies' own."""

from __future__ import annotations

import pytest

from facing_service.config.profiles import engagement_params, head_profile, scene_params
from facing_service.config.settings import Settings
from facing_service.core.engagement import Model, facing_score


def test_a_faces_score_crosses_engage_above_at_the_edge_of_its_cone():
    settings = Settings()
    profile = head_profile(settings)
    edge = settings.head_threshold_deg
    assert facing_score(edge, 1.0, profile.engagement) == pytest.approx(settings.engage_above)
    assert profile.threshold_deg == edge and profile.hysteresis_deg == settings.hysteresis_deg


def test_the_rule_is_everyones_and_the_evidence_model_only_the_heads():
    rule = Settings(engagement="rule")
    assert engagement_params(rule).model is Model.RULE
    assert head_profile(rule).engagement.model is Model.RULE
    evidence = Settings(head_model="evidence")
    assert engagement_params(evidence).model is Model.CONE
    assert head_profile(evidence).engagement.model is Model.EVIDENCE


def test_who_faces_whom_is_the_bodies_facing_rule():
    params = scene_params(Settings(threshold_deg=25, hysteresis_deg=4, group_rate_hz=5))
    assert (params.threshold_deg, params.hysteresis_deg, params.period_s) == (25, 4, 0.2)
