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
