"""What makes a test fail in the project's CI where a contributor's clone skips it (the shared
data, a system package): the project's own variables, set by .ci/run, never the ``CI=true``
hosted CIs set for every fork (a user's fork on GitHub Actions failed on data it
cannot have)."""

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


def test_every_system_package_a_test_needs_is_in_the_readme_and_installed_by_ci():
    """A defect found: the packages were listed only inside .ci/run, and a fresh clone's test
    command failed on them. The README's install line, CI's installs and the tests' list
    are one set; CI makes a missing one fail, a contributor's clone skips its tests."""
    from system_packages import PACKAGES, REQUIRE_SYSTEM_PACKAGES

    readme = (CI_RUN.parents[1] / "README.md").read_text()
    line = readme.split("<!-- system-packages -->", 1)[1].split("```bash\n", 1)[1]
    assert line.split("\n", 1)[0].split()[3:] == list(PACKAGES)
    ci = CI_RUN.read_text()
    assert all(f"need+=({package})" in ci for package in PACKAGES)
    assert f"export {REQUIRE_SYSTEM_PACKAGES}=1\n" in ci


def test_a_missing_system_package_skips_its_test_on_a_clone_and_fails_it_in_ci(
    monkeypatch: pytest.MonkeyPatch,
):
    import system_packages

    monkeypatch.setattr(system_packages, "present", lambda package: False)
    monkeypatch.delenv(system_packages.REQUIRE_SYSTEM_PACKAGES, raising=False)
    with pytest.raises(pytest.skip.Exception, match="apt-get install chromium"):
        system_packages.require("chromium")
    monkeypatch.setenv(system_packages.REQUIRE_SYSTEM_PACKAGES, "1")
    with pytest.raises(pytest.fail.Exception, match="CI runs every test"):
        system_packages.require("chromium")


def test_the_test_commands_lines_together_run_every_test_once():
    """The README's test command runs the benchmarks' figures beside the rest, each line in
    an environment of its own (they run at once in CI): one line deselects exactly what
    another selects, and no two lines share an environment."""
    readme = (CI_RUN.parents[1] / "README.md").read_text()
    block = readme.split("<!-- test-command", 1)[1].split("```bash\n", 1)[1].split("```", 1)[0]
    lines = block.strip().splitlines()
    assert sum(line.endswith('pytest -m "not figures"') for line in lines) == 1, lines
    assert sum(line.endswith("pytest -m figures") for line in lines) == 1, lines
    venvs = [line.split()[3] for line in lines]  # python3 -m venv <env> && ...
    assert len(set(venvs)) == len(lines), venvs
    for venv, line in zip(venvs, lines, strict=True):
        assert f"{venv}/bin/python -m pytest" in line, line
