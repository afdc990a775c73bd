"""What makes a test of the shared data fail instead of skipping: the project's own
variable, set by .ci/run, never the ``CI=true`` hosted CIs set for every fork (issue 67:
a user's fork on GitHub Actions failed on data it cannot have)."""

from __future__ import annotations

from pathlib import Path

import pytest

from oracles import REQUIRE_SHARED_DATA, shared_data_required

CI_RUN = Path(__file__).resolve().parents[1] / ".ci" / "run"


def test_a_hosted_ci_alone_does_not_require_the_shared_data(monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setenv("CI", "true")
    monkeypatch.delenv(REQUIRE_SHARED_DATA, raising=False)
    assert not shared_data_required()
    monkeypatch.setenv(REQUIRE_SHARED_DATA, "1")
    assert shared_data_required()


def test_the_projects_ci_requires_it():
    assert f"export {REQUIRE_SHARED_DATA}=1\n" in CI_RUN.read_text()


def test_the_variable_is_no_setting_a_command_would_say_is_misspelt():
    """CI's first run with it named FACING_REQUIRE_SHARED_DATA: every command the tests
    started said "FACING_REQUIRE_SHARED_DATA names no setting and is ignored", and the
    tests that read their stderr failed. FACING_TEST_* is the tooling's."""
    from facing_service.config.sources import unknown_variables

    assert unknown_variables({REQUIRE_SHARED_DATA: "1"}) == []
    assert unknown_variables({"FACING_REQUIRE_SHARED_DATA": "1"}) != []  # what it was
