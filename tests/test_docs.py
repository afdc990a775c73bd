"""The documentation states facts the code owns; these tests keep the two equal. (The
commands the docs show are checked in test_docs_commands.py; the performance tables in
test_benchmarks.py; the security recipe in test_router_secure.py.)"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from facing_service.contract.poses import Rejection
from facing_service.shell.ledger import COUNTERS

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.glob("*.md"))
LINK = re.compile(r"\]\(([^)\s]+)\)")


def test_the_readme_is_short_and_links_every_page():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) <= 200
    linked = {target.split("#")[0] for target in LINK.findall(readme)}
    assert {f"docs/{page.name}" for page in PAGES} <= linked


@pytest.mark.parametrize("doc", [ROOT / "README.md", *PAGES], ids=lambda p: p.name)
def test_relative_links_resolve(doc):
    for target in LINK.findall(doc.read_text()):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue
        path = (doc.parent / target.split("#")[0]).resolve()
        assert path.exists(), f"{doc.name} links to {target}, which does not exist"


def test_the_contract_names_every_rejection_reason_and_no_other():
    page = (DOCS / "contract.md").read_text()
    table = set(re.findall(r"(?m)^\| `([a-z_]+)` \|", page))
    ros = {r for r in Rejection if r.value.startswith("tf_")} | {
        Rejection.TYPE_MISMATCH,
        Rejection.MALFORMED_CDR,
        Rejection.INVALID_ID,
        Rejection.LINK_TAKEN,
    }
    assert table == {r.value for r in Rejection} - {r.value for r in ros}
    for reason in ros:
        assert f"`{reason.value}`" in page


def test_the_status_example_shows_every_counter():
    page = (DOCS / "operations.md").read_text()
    counters = re.search(r'"counters": (\{.*?\})', page, re.S)
    assert counters is not None
    assert list(json.loads(counters[1])) == list(COUNTERS)


def test_the_configuration_table_is_the_settings():
    """docs/configuration.md's table is generated from the Settings fields' descriptions,
    like the CLI's help: change a setting, and this says what the page must become."""
    from facing_service.config.sources import settings_table

    page = (DOCS / "configuration.md").read_text()
    table = re.search(r"<!-- settings: .*?-->\n(.*?)\n<!-- end of settings -->", page, re.S)
    assert table is not None
    assert table[1] == settings_table(), (
        "regenerate: python -c 'from facing_service.config.sources import settings_table; "
        "print(settings_table())'"
    )


def test_no_recipe_backgrounds_the_live_view():
    """`watch` redraws its terminal: a recipe that runs it with `&` beside another command
    mixes their output (and leaves jobs nobody is told how to stop)."""
    for doc in [ROOT / "README.md", *sorted(DOCS.glob("*.md"))]:
        for line in doc.read_text().splitlines():
            if "facing-service watch" in line:
                assert not line.rstrip().endswith("&"), f"{doc.name}: {line}"


def test_the_engagement_tables_are_the_committed_results():
    """docs/engagement.md's cross-validation and docs/ros2.md's real-path tables are
    generated from benchmarks/results/recordings.json: a figure copied by hand, or a
    results file rewritten without its pages, fails here."""
    from benchmarks import engagement_report

    assert engagement_report.main(["--check"]) == 0, (
        "regenerate: python -m benchmarks.engagement_report"
    )


def test_the_groups_tables_are_the_committed_results():
    """docs/groups.md's held-out tables are generated from benchmarks/results/groups.json
    (`python -m benchmarks.groups --live --out ...`): a figure copied by hand fails here."""
    from benchmarks import groups

    assert groups.main(["--page", "--check"]) == 0, "regenerate: python -m benchmarks.groups --page"


@pytest.mark.slow
def test_the_readmes_isolated_run_and_its_snippet_work_as_written():
    """The README shows the isolated way first: the service on loopback without
    multicast scouting, and a snippet that connects to it alone. Both run as written
    (only the port changes), and the snippet prints the service's result."""
    import subprocess
    import sys

    from facing_service.testing import free_port, running_cli

    readme = (ROOT / "README.md").read_text()
    run = re.search(r"`\.venv/bin/facing-service (run -l tcp/127\.0\.0\.1:7447[^`]*)`", readme)
    snippet = re.search(r"python - <<'EOF'\n(.*?)\nEOF", readme, re.S)
    assert run and snippet
    port = str(free_port())
    with running_cli(*run[1].replace("7447", port).split()):
        done = subprocess.run(
            [sys.executable, "-c", snippet[1].replace("7447", port)],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip
    assert done.returncode == 0, done.stderr
    (result,) = [json.loads(line) for line in done.stdout.splitlines()]
    assert result["body_id"] == "alice" and result["facing"] is True


def test_performance_figures_are_stated_once_on_the_performance_page():
    """Figures drifted between pages (1.65x on one, 1.89x on another, against two different
    targets): the measured ratios and rates live on docs/performance.md, generated from
    benchmarks/results/latest.json (test_benchmarks.py checks the two agree); every other
    page links there instead of copying them."""
    figure = re.compile(r"\d+\.\d+ ?\u00d7|poses/s|of one core")
    for doc in [ROOT / "README.md", *PAGES]:
        if doc.name == "performance.md":
            continue
        found = figure.findall(doc.read_text())
        assert not found, f"{doc.name} states performance figures {found}: link performance.md"
