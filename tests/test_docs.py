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


def anchors(page: Path) -> set[str]:
    """The anchors GitHub gives a Markdown page's headings: lower case, punctuation
    dropped, spaces as hyphens, a repeated one numbered (-1, -2 …)."""
    seen: dict[str, int] = {}
    out = set()
    text = re.sub(r"(?ms)^```.*?^```", "", page.read_text())  # no headings in code blocks
    for heading in re.findall(r"(?m)^#{1,6} +(.+?) *#*$", text):
        slug = re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")
        out.add(slug if slug not in seen else f"{slug}-{seen[slug]}")
        seen[slug] = seen.get(slug, 0) + 1
    return out


@pytest.mark.parametrize(
    "doc",
    [
        ROOT / "README.md",
        *PAGES,
        ROOT / "examples" / "README.md",
        ROOT / "benchmarks" / "README.md",
    ],
    ids=lambda p: str(p.relative_to(ROOT)),
)
def test_relative_links_resolve_anchors_included(doc):
    """A defect found: two pages linked an anchor that had changed; a page's link and the
    heading it names are checked together."""
    for target in LINK.findall(doc.read_text()):
        if re.match(r"[a-z]+:", target):
            continue
        file, _, anchor = target.partition("#")
        path = (doc.parent / file).resolve() if file else doc
        assert path.exists(), f"{doc.name} links to {target}, which does not exist"
        if anchor and path.suffix == ".md":
            assert anchor in anchors(path), f"{doc.name} links to {target}: no such heading"


def test_the_contract_names_every_rejection_reason_and_no_other():
    page = (DOCS / "contract.md").read_text()
    table = set(re.findall(r"(?m)^\| `([a-z_]+)` \|", page))
    ros = {r for r in Rejection if r.value.startswith("tf_")} | {
        Rejection.TYPE_MISMATCH,
        Rejection.MALFORMED_CDR,
        Rejection.INVALID_ID,
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
    from benchmarks.engagement import report as engagement_report

    assert engagement_report.main(["--check"]) == 0, (
        "regenerate: python -m benchmarks.engagement.report"
    )


def test_the_groups_tables_are_the_committed_results():
    """docs/groups.md's held-out tables are generated from benchmarks/results/groups.json
    (`python -m benchmarks.groups.held_out --out ...`): a figure copied by hand
    fails here."""
    from benchmarks.groups import held_out as groups

    assert groups.main(["--page", "--check"]) == 0, (
        "regenerate: python -m benchmarks.groups.held_out --page"
    )


@pytest.mark.slow
def test_the_readmes_isolated_run_its_health_check_and_its_snippet_work_as_written(net):
    """The README shows the isolated way first: the service on loopback without
    multicast scouting, the health command that reaches it, and a snippet that connects
    to it alone. Each runs as written, in the README's order (only the port changes),
    beside another service on this host (plain `health` answered for that one):
    health names our instance and endpoint, the snippet prints the service's result, and
    no command prints a traceback or exits 0 having heard nothing."""
    import signal
    import subprocess
    import sys

    from facing_service.testing import endpoint, free_port, running_cli

    readme = " ".join((ROOT / "README.md").read_text().split())  # commands wrap lines
    run = re.search(r"`\.venv/bin/facing-service (run -l tcp/127\.0\.0\.1:7447[^`]*)`", readme)
    health = re.search(
        r"`\.venv/bin/facing-service (health -e tcp/127\.0\.0\.1:7447[^`]*)`", readme
    )
    snippet = re.search(r"python - <<'EOF'\n(.*?)\nEOF", (ROOT / "README.md").read_text(), re.S)
    assert run and health and snippet
    assert readme.index(run[0]) < readme.index(health[0]) < readme.index("python - <<'EOF'")
    net.service(listen=[endpoint(free_port())], instance="someone-else")  # another service
    port = str(free_port())
    with running_cli(*run[1].replace("7447", port).split(), env={"FACING_INSTANCE": "ours"}) as svc:
        checked = subprocess.run(
            [sys.executable, "-m", "facing_service", *health[1].replace("7447", port).split()],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip
        done = subprocess.run(
            [sys.executable, "-c", snippet[1].replace("7447", port)],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip
        svc.send_signal(signal.SIGTERM)
        said, _ = svc.communicate(timeout=10)
    assert svc.returncode == 0 and "Traceback" not in said, said
    for proc in (checked, done):
        assert proc.returncode == 0 and "Traceback" not in proc.stdout + proc.stderr, proc
    (line,) = checked.stdout.splitlines()
    assert line.startswith("ok: instance ours (facing-service ") and f":{port}," in line, line
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


def test_the_examples_are_run_with_the_venvs_python():
    """A defect found: examples/README said `python examples/tracker.py`, a ModuleNotFoundError
    (zenoh) unless the venv was active."""
    texts = [*ROOT.glob("*.md"), *PAGES, *ROOT.glob("examples/**/*.md"),
             *ROOT.glob("examples/*.py")]  # fmt: skip
    bare = re.compile(r"(?<![\w/.-])python3? examples/")
    said = [f"{p.relative_to(ROOT)}: {m.group(0)}" for p in texts for m in bare.finditer(
        p.read_text())]  # fmt: skip
    assert said == []
